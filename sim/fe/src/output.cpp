#include <algorithm>

#include <fmt/format.h>

#include "tocd/core/error.hpp"
#include "tocd/sim/fe/solve.hpp"

namespace tocd::sim::fe {

namespace {
nlohmann::json points(const std::vector<Point2>& p) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& q : p) a.push_back({q.r_mm, q.z_mm});
  return a;
}
}  // namespace

nlohmann::json to_json(const FeResult& r, bool with_geometry) {
  const FeModel& m = r.model;
  nlohmann::json j;
  j["model"] = {
      {"thickness_mm", m.thickness_mm},
      {"outer_radius_mm", m.outer_radius_mm},
      {"pin_radius_mm", m.pin_radius_mm},
      {"kinematics", to_string(m.kinematics)},
      {"bottom", to_string(m.bottom)},
      {"mesh_refinement", m.mesh_refinement},
      {"material", {{"mu_MPa", m.material.mu}, {"alpha", m.material.alpha}, {"D_per_MPa", m.material.D}}}};
  if (m.kinematics != Kinematics::axisymmetric) j["model"]["depth_mm"] = m.depth_mm;
  j["complete"] = r.complete;
  j["stop_reason"] = r.stop_reason;
  j["newton_iterations"] = r.total_newton_iterations;
  j["load_increments"] = r.total_load_increments;
  j["seconds"] = r.seconds;
  nlohmann::json steps = nlohmann::json::array();
  for (const auto& s : r.steps) {
    nlohmann::json e = {{"displacement_mm", s.displacement_mm},
                        {"nominal_strain", s.displacement_mm / m.thickness_mm},
                        {"force_N", s.force_N},
                        {"compressed_area_mm2", s.compressed_area_mm2},
                        {"compressed_volume_mm3", s.compressed_volume_mm3},
                        {"min_log_strain", s.element_min_log_strain.empty()
                                               ? 0.0
                                               : *std::min_element(s.element_min_log_strain.begin(),
                                                                   s.element_min_log_strain.end())},
                        {"contact_radius_mm", s.contact_radius_mm},
                        {"max_penetration_mm", s.max_penetration_mm},
                        {"newton_iterations", s.newton_iterations},
                        {"load_increments", s.load_increments}};
    if (with_geometry) {
      e["top_surface"] = points(s.top_surface);
      nlohmann::json outlines = nlohmann::json::array();
      for (const auto& o : s.compressed_outlines) outlines.push_back(points(o));
      e["compressed_outlines"] = outlines;
    }
    steps.push_back(e);
  }
  j["steps"] = steps;
  return j;
}

void write_vtu(const FeStepResult& s, const std::filesystem::path& path, vtk::Format format) {
  const auto& m = s.mesh;
  if (s.displacement.size() != m.nodes.size())
    throw tocd::Error(
        fmt::format("FE step: {} displacements for {} nodes", s.displacement.size(), m.nodes.size()));
  // One convention (docs/fe.md): points at their reference (undeformed) place plus the
  // displacement field, so ParaView's Warp By Vector at scale 1 shows the deformed shape
  // once. The step holds the deformed mesh; reference = deformed - displacement.
  vtk::UnstructuredGrid g;
  g.points_xyz.reserve(3 * m.nodes.size());
  std::vector<double> displacement;
  displacement.reserve(3 * m.nodes.size());
  for (std::size_t n = 0; n < m.nodes.size(); ++n) {
    const Point2 u = s.displacement[n];
    g.points_xyz.insert(g.points_xyz.end(), {m.nodes[n].r_mm - u.r_mm, m.nodes[n].z_mm - u.z_mm, 0.0});
    displacement.insert(displacement.end(), {u.r_mm, u.z_mm, 0.0});
  }
  for (const auto& q : m.quads) g.connectivity.insert(g.connectivity.end(), {q[0], q[1], q[2], q[3]});
  g.nodes_per_cell = 4;
  g.cell_type = 9;  // VTK_QUAD
  g.point_data.push_back({"displacement", 3, std::move(displacement)});
  g.active_point_vectors = "displacement";
  std::vector<std::uint8_t> compressed;
  for (const double e : s.element_min_log_strain) compressed.push_back(e <= s.compressed_log_strain ? 1 : 0);
  g.cell_data.push_back({"min_log_strain", 1, s.element_min_log_strain});
  g.cell_data.push_back({"J", 1, s.element_J});
  g.cell_data.push_back({"compressed", 1, std::move(compressed)});
  vtk::write_vtu(g, path, format);
}

}  // namespace tocd::sim::fe

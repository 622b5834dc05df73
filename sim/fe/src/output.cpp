#include <algorithm>
#include <fstream>

#include <fmt/format.h>

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

void write_vtu(const FeStepResult& s, const std::filesystem::path& path) {
  std::ofstream out(path);
  if (!out) throw tocd::Error(fmt::format("cannot write {}", path.string()));
  const auto& m = s.mesh;
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
         "byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n<UnstructuredGrid>\n";
  out << fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", m.nodes.size(), m.quads.size());
  out << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : m.nodes) out << fmt::format("{:.9g} {:.9g} 0\n", p.r_mm, p.z_mm);
  out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" "
         "format=\"ascii\">\n";
  for (const auto& q : m.quads) out << fmt::format("{} {} {} {}\n", q[0], q[1], q[2], q[3]);
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 1; i <= m.quads.size(); ++i) out << 4 * i << (i % 16 == 0 ? '\n' : ' ');
  out << "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 1; i <= m.quads.size(); ++i) out << "9" << (i % 32 == 0 ? '\n' : ' ');  // VTK_QUAD
  out << "\n</DataArray>\n</Cells>\n<PointData Vectors=\"displacement\">\n"
         "<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& d : s.displacement) out << fmt::format("{:.9g} {:.9g} 0\n", d.r_mm, d.z_mm);
  out << "</DataArray>\n</PointData>\n<CellData Scalars=\"min_log_strain\">\n";
  auto doubles = [&](const char* name, const std::vector<double>& v) {
    out << fmt::format("<DataArray type=\"Float64\" Name=\"{}\" format=\"ascii\">\n", name);
    for (std::size_t i = 0; i < v.size(); ++i)
      out << fmt::format("{:.9g}{}", v[i], (i + 1) % 8 == 0 ? '\n' : ' ');
    out << "\n</DataArray>\n";
  };
  doubles("min_log_strain", s.element_min_log_strain);
  doubles("J", s.element_J);
  out << "<DataArray type=\"UInt8\" Name=\"compressed\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < s.element_min_log_strain.size(); ++i)
    out << (s.element_min_log_strain[i] <= -0.5 ? 1 : 0) << ((i + 1) % 32 == 0 ? '\n' : ' ');
  out << "\n</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  if (!out) throw tocd::Error(fmt::format("error writing {}", path.string()));
}

}  // namespace tocd::sim::fe

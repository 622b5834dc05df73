#include "tocd/sim/geometry/composite.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "layout.hpp"
#include "plc.hpp"
#include "region_classifier.hpp"
#include "tetgen_mesher.hpp"

namespace tocd::sim::geometry {

namespace {

/// Volumes of each region from the layout's polygons: boxes exactly, revolved parts by
/// Pappus' theorem with the N-gon factor N sin(2 pi / N) / (2 pi) (every revolved cross-
/// section is a regular N-gon, so this is exact for the meshed complex).
std::vector<double> expected_volumes(const detail::Layout& L, int n) {
  const double ngon = n * std::sin(2.0 * std::numbers::pi / n);  // times int r dA
  const double area = 4.0 * L.half_mm * L.half_mm;
  std::vector<double> v(6, 0.0);
  v[pin] = ngon * std::abs(detail::integral_r_dA(L.pin_polygon));
  v[slide] = area * L.slide_thickness_mm;
  double skin_total = 0;
  if (!L.baseline) {
    skin_total = area * L.skin_top_mm - ngon * detail::integral_r_dA(L.depression_polygon);
    for (const auto& poly : L.compressed_polygons)
      v[compressed] += ngon * std::abs(detail::integral_r_dA(poly));
    v[skin] = skin_total - v[compressed];
  }
  v[air] = area * L.z_top_mm - skin_total - v[pin];
  return v;
}

std::string switches_for(const ResolvedSize& size) {
  return fmt::format("pq{}/{}a{}Q", size.radius_edge_ratio, size.min_dihedral_deg, size.max_volume_mm3);
}

}  // namespace

CompositeMesh build_composite(const CompositeSpec& spec, const std::atomic<bool>* cancel) {
  const auto t0 = std::chrono::steady_clock::now();
  check_mesh_size(spec);
  CompositeMesh result;
  result.size = resolve_size(spec.size);
  const detail::Layout layout =
      detail::build_layout(spec, result.size.section_edge_mm, result.size.tip_edge_mm);
  const detail::Plc plc = detail::build_plc(layout, result.size.azimuth_segments);
  result.tetgen_switches = switches_for(result.size);
  result.mesh = detail::tetrahedralize(plc, layout.section, result.tetgen_switches, cancel);
  detail::assign_regions(result.mesh, layout, result.size.azimuth_segments);
  result.contact_radius_mm = layout.contact_radius_mm;

  const auto expected = expected_volumes(layout, result.size.azimuth_segments);
  std::vector<std::size_t> tets(6, 0);
  std::vector<double> volume(6, 0.0);
  for (std::size_t t = 0; t < result.mesh.tets.size(); ++t) {
    const auto r = static_cast<std::size_t>(result.mesh.regions[t]);
    ++tets[r];
    volume[r] += tocd::sim::mesh::tet_volume(result.mesh, t);
  }
  for (int r = pin; r <= compressed; ++r) {
    if (tets[static_cast<std::size_t>(r)] == 0 && expected[static_cast<std::size_t>(r)] == 0) continue;
    result.regions.push_back({r, tets[static_cast<std::size_t>(r)], volume[static_cast<std::size_t>(r)],
                              expected[static_cast<std::size_t>(r)]});
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace tocd::sim::geometry

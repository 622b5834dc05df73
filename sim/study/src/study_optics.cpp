#include "tocd/sim/study/study_optics.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "graded_levels.hpp"
#include "json_keys.hpp"
#include "json_whole_number.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/geometry/composite.hpp"

namespace tocd::sim::study {
namespace geo = tocd::sim::geometry;

mc::RegionOptics air_optics() {
  return {0.001, 0.001, 1.0, 1.003, "air"};
}
mc::RegionOptics glass_optics() {
  return {0.001, 0.001, 1.0, 1.458, "glass"};
}
mc::RegionOptics native_skin_optics() {
  return {0.089, 28.9, 0.926, 1.38, "skin"};
}
mc::RegionOptics cleared_skin_optics() {
  return {0.0534, 17.34, 0.926, 1.518, "cleared skin"};
}

mc::Optics threshold_optics(const mc::RegionOptics& compressed) {
  mc::Optics o;
  o.ambient_n = 1.0;
  auto glass = glass_optics();
  glass.name = "pin";
  o.regions[geo::Region::pin] = glass;
  glass.name = "slide";
  o.regions[geo::Region::slide] = glass;
  o.regions[geo::Region::air] = air_optics();
  o.regions[geo::Region::skin] = native_skin_optics();
  auto c = compressed;
  if (c.name.empty()) c.name = "compressed skin";
  o.regions[geo::Region::compressed] = c;
  mc::validate(o, "study optics");
  return o;
}

namespace {
void check(const GradedOptics& g) {
  if (g.bins < 1 || g.bins > 1000)
    throw tocd::ConfigError(fmt::format("graded optics: bins must be 1..1000, got {}", g.bins));
  if (!(g.full_strain > 0.0))
    throw tocd::ConfigError(fmt::format("graded optics: full_strain must be > 0, got {}", g.full_strain));
}
}  // namespace

int graded_level(double min_log_strain, const GradedOptics& graded) {
  check(graded);
  if (std::isnan(min_log_strain)) return 0;
  const double f = std::clamp(-min_log_strain / graded.full_strain, 0.0, 1.0);
  return static_cast<int>(std::lround(f * graded.bins));
}

mc::RegionOptics graded_optics_at(double f, const GradedOptics& graded) {
  f = std::clamp(f, 0.0, 1.0);
  const auto& a = graded.native;
  const auto& b = graded.cleared;
  auto mix = [f](double x, double y) { return x + f * (y - x); };
  return {mix(a.mu_a_per_mm, b.mu_a_per_mm), mix(a.mu_s_per_mm, b.mu_s_per_mm), a.g, mix(a.n, b.n),
          fmt::format("skin f={:.3f}", f)};
}

mc::Optics graded_optics(const GradedOptics& graded) {
  check(graded);
  mc::Optics o = threshold_optics(graded.cleared);
  o.regions.erase(geo::Region::compressed);
  o.regions[geo::Region::skin] = graded.native;
  for (int k = 1; k <= graded.bins; ++k)
    o.regions[kGradedRegionBase + k] = graded_optics_at(static_cast<double>(k) / graded.bins, graded);
  mc::validate(o, "graded optics");
  return o;
}

std::vector<std::size_t> detail::assign_graded_levels(
    mesh::TetMesh& mesh, int bins, const std::function<int(double r, double z)>& level_at) {
  std::vector<std::size_t> counts(static_cast<std::size_t>(std::max(bins, 0)) + 1, 0);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto region = mesh.regions[t];
    if (region != geo::Region::skin && region != geo::Region::compressed) continue;
    mesh::Point3 c{0, 0, 0};
    for (int v = 0; v < 4; ++v)
      for (int k = 0; k < 3; ++k) c[k] += 0.25 * mesh.nodes[static_cast<std::size_t>(mesh.tets[t][v])][k];
    const int level = level_at(std::hypot(c[0], c[1]), c[2]);
    mesh.regions[t] = level == 0 ? geo::Region::skin : kGradedRegionBase + level;
    ++counts[static_cast<std::size_t>(level)];
  }
  return counts;
}

std::vector<std::size_t> assign_graded_regions(mesh::TetMesh& mesh, const GradedOptics& graded,
                                               const std::function<double(double, double)>& min_log_strain) {
  check(graded);
  return detail::assign_graded_levels(
      mesh, graded.bins, [&](double r, double z) { return graded_level(min_log_strain(r, z), graded); });
}

nlohmann::json to_json(const mc::RegionOptics& o) {
  return {{"mu_a", o.mu_a_per_mm}, {"mu_s", o.mu_s_per_mm}, {"g", o.g}, {"n", o.n}, {"name", o.name}};
}

mc::RegionOptics region_optics_from_json(const nlohmann::json& j) {
  require_known_keys(j, {"mu_a", "mu_s", "g", "n", "name"}, "optics in config");
  try {
    mc::RegionOptics o{j.at("mu_a").get<double>(), j.at("mu_s").get<double>(), j.at("g").get<double>(),
                       j.at("n").get<double>(), j.value("name", std::string{})};
    mc::Optics check_one;
    check_one.regions[0] = o;
    mc::validate(check_one, "optics in config");
    return o;
  } catch (const nlohmann::json::exception& e) {
    throw tocd::ConfigError(
        fmt::format("optics in config: expected mu_a, mu_s, g, n numbers ({})", e.what()));
  }
}

nlohmann::json to_json(const GradedOptics& g) {
  return {{"native", to_json(g.native)},
          {"cleared", to_json(g.cleared)},
          {"full_strain", g.full_strain},
          {"bins", g.bins}};
}

GradedOptics graded_from_json(const nlohmann::json& j) {
  GradedOptics g;
  require_known_keys(j, {"native", "cleared", "full_strain", "bins"}, "graded optics in config");
  try {
    g.native = region_optics_from_json(j.at("native"));
    g.cleared = region_optics_from_json(j.at("cleared"));
    g.full_strain = j.at("full_strain").get<double>();
    g.bins = static_cast<int>(json_whole_number(j.at("bins"), "graded optics in config: bins", 1, 1000));
  } catch (const nlohmann::json::exception& e) {
    throw tocd::ConfigError(fmt::format("graded optics in config: {}", e.what()));
  }
  check(g);
  return g;
}

}  // namespace tocd::sim::study

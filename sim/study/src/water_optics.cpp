#include "tocd/sim/study/water_optics.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "graded_levels.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/geometry/composite.hpp"

namespace tocd::sim::study {

namespace geo = tocd::sim::geometry;

double native_water_fraction(const WaterOptics& w) {
  const double f = (w.dry_index - w.graded.native.n) / (w.dry_index - w.water_index);
  if (!(f > 0 && f < 1))
    throw tocd::ConfigError(
        fmt::format("water optics: native index {} is not between water ({}) and dry tissue ({})",
                    w.graded.native.n, w.water_index, w.dry_index));
  return f;
}

double mixed_index(double water_fraction, const WaterOptics& w) {
  const double x = std::clamp(water_fraction, 0.0, 1.0);
  return x * w.water_index + (1 - x) * w.dry_index;
}

double water_clearing_fraction(double water_fraction, const WaterOptics& w) {
  if (std::isnan(water_fraction)) return 0;
  const double span = w.graded.cleared.n - w.graded.native.n;
  if (!(span > 0)) throw tocd::ConfigError("water optics: the cleared index must exceed the native index");
  return std::clamp((mixed_index(water_fraction, w) - w.graded.native.n) / span, 0.0, 1.0);
}

int water_level(double water_fraction, const WaterOptics& w) {
  if (w.graded.bins < 1 || w.graded.bins > 1000)
    throw tocd::ConfigError(fmt::format("water optics: bins must be 1..1000, got {}", w.graded.bins));
  return static_cast<int>(std::lround(water_clearing_fraction(water_fraction, w) * w.graded.bins));
}

mc::Optics water_optics(const WaterOptics& w) {
  native_water_fraction(w);  // validates the index end points
  return graded_optics(w.graded);
}

std::vector<std::size_t> assign_water_regions(mesh::TetMesh& mesh, const WaterOptics& w,
                                              const std::function<double(double, double)>& water_fraction) {
  return detail::assign_graded_levels(
      mesh, w.graded.bins, [&](double r, double z) { return water_level(water_fraction(r, z), w); });
}

}  // namespace tocd::sim::study

#include "window_check.hpp"

#include <cmath>

#include <fmt/format.h>

namespace tocd::acquisition {

std::string window_problems(const WindowRequirements& need, const WindowObservation& seen) {
  std::string out;
  const auto add = [&](const std::string& s) { out += (out.empty() ? "" : "; ") + s; };
  if (seen.faults > 0) add(fmt::format("{} instrument fault(s) during the window", seen.faults));
  for (int s = 0; s < kSlots; ++s) {
    if (!(need.rate_Hz[s] > 0)) continue;
    const double expected = std::floor(need.record_s * need.rate_Hz[s]);
    const auto n = seen.stats[s].n();
    if (static_cast<double>(n) < need.min_sample_fraction * expected) {
      add(fmt::format("{} {} readings of {} expected (at least {:.0f} % needed)", n, kChannelNames[s],
                      expected, need.min_sample_fraction * 100.0));
    }
  }
  if (need.target_displacement_mm) {
    const double d = seen.stats[kDisplacement].mean();
    if (!(std::abs(d - *need.target_displacement_mm) <= need.position_tolerance_mm)) {
      add(fmt::format("mean displacement {:.4f} mm is not within {} mm of the target {} mm", d,
                      need.position_tolerance_mm, *need.target_displacement_mm));
    }
  }
  const double T = seen.stats[kPower].mean() / need.baseline_W;
  if (!(std::isfinite(T) && T > 0.0)) {
    add(fmt::format("transmission {:.4g} (mean power {:.4g} W) is not a positive number", T,
                    seen.stats[kPower].mean()));
  }
  return out;
}

}  // namespace tocd::acquisition

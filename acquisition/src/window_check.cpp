#include "window_check.hpp"

#include <cmath>

#include <fmt/format.h>

namespace tocd::acquisition {

RunningStats slot_stats(const WindowObservation& seen, int slot) {
  if (slot < 0 || static_cast<std::size_t>(slot) >= seen.stats.size()) return {};
  return seen.stats[static_cast<std::size_t>(slot)];
}

std::string window_problems(const WindowRequirements& need, const WindowObservation& seen) {
  std::string out;
  const auto add = [&](const std::string& s) { out += (out.empty() ? "" : "; ") + s; };
  if (seen.faults > 0) add(fmt::format("{} instrument fault(s) during the window", seen.faults));
  for (std::size_t s = 0; s < need.channels.size(); ++s) {
    const WindowChannel& ch = need.channels[s];
    if (!(ch.rate_Hz > 0)) continue;
    const double expected = std::floor(need.record_s * ch.rate_Hz);
    const auto n = slot_stats(seen, static_cast<int>(s)).n();
    if (static_cast<double>(n) < need.min_sample_fraction * expected) {
      add(fmt::format("{} {} readings of {} expected (at least {:.0f} % needed)", n, ch.name, expected,
                      need.min_sample_fraction * 100.0));
    }
  }
  if (need.target_displacement_mm) {
    const double d = slot_stats(seen, need.displacement_slot).mean();
    if (!(std::abs(d - *need.target_displacement_mm) <= need.position_tolerance_mm)) {
      add(fmt::format("mean displacement {:.4f} mm is not within {} mm of the target {} mm", d,
                      need.position_tolerance_mm, *need.target_displacement_mm));
    }
  }
  const double power_W = slot_stats(seen, need.power_slot).mean();
  const double T = power_W / need.baseline_W;
  if (!(std::isfinite(T) && T > 0.0)) {
    add(fmt::format("transmission {:.4g} (mean power {:.4g} W) is not a positive number", T, power_W));
  }
  return out;
}

}  // namespace tocd::acquisition

#include <algorithm>
#include <array>
#include <cmath>

#include "tocd/plot/figures.hpp"

namespace tocd::plot {

Rgb fluence_ramp(double t) {
  // Viridis (van der Walt and Smith, matplotlib 2.0) sampled at t = 0, 1/8, ..., 1; linear
  // between samples. Its lightness rises monotonically from dark violet to yellow.
  static constexpr std::array<std::array<int, 3>, 9> kStops{{{68, 1, 84},
                                                             {71, 44, 122},
                                                             {59, 81, 139},
                                                             {44, 113, 142},
                                                             {33, 144, 141},
                                                             {39, 173, 129},
                                                             {92, 200, 99},
                                                             {170, 220, 50},
                                                             {253, 231, 37}}};
  if (!std::isfinite(t)) t = 0.0;
  t = std::clamp(t, 0.0, 1.0) * (kStops.size() - 1);
  const auto i = std::min<std::size_t>(static_cast<std::size_t>(t), kStops.size() - 2);
  const double f = t - static_cast<double>(i);
  auto mix = [&](int c) {
    return static_cast<int>(std::lround(kStops[i][c] + f * (kStops[i + 1][c] - kStops[i][c])));
  };
  return {mix(0), mix(1), mix(2)};
}

}  // namespace tocd::plot

#pragma once
#include <cmath>
#include <vector>
// The closed-form poroelastic checks run twice: in the physics suite at a base resolution, and
// under physics-long (built with TOCD_PORO_LONG) on meshes and time steps twice as fine, as
// suites of their own names so that both can be selected and reported apart.

#ifdef TOCD_PORO_LONG
inline constexpr int kPoroRefinement = 2;
#define TOCD_PORO_SUITE(name) name##Long
#else
inline constexpr int kPoroRefinement = 1;
#define TOCD_PORO_SUITE(name) name
#endif

/// Dimensionless times from T0 to T1, both included, spaced geometrically at `per_decade` steps a
/// decade: the backward-Euler time steps of the closed-form checks.
inline std::vector<double> geometric_times(double T0, double T1, int per_decade) {
  const int steps = static_cast<int>(per_decade * std::log10(T1 / T0));
  std::vector<double> times;
  for (int n = 0; n <= steps; ++n) times.push_back(T0 * std::pow(T1 / T0, double(n) / steps));
  return times;
}

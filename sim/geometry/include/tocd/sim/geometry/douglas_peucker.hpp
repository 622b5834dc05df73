#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace tocd::sim::geometry {

/// Douglas-Peucker over the points 0 .. n-1 of a polyline (n >= 2): the indices, in order and
/// ends included, of the points it keeps so that every dropped point lies within `tolerance`
/// of the chord between the kept points around it. `deviation(i, a, b)` is point i's distance
/// from the chord a-b in the caller's measure (a section's outline: in the plane; a recorded
/// displacement history: in displacement at the sample's own time).
template <class Deviation>
std::vector<std::size_t> douglas_peucker(std::size_t n, double tolerance, Deviation deviation) {
  std::vector<char> keep(n, 0);
  keep.front() = keep.back() = 1;
  std::vector<std::pair<std::size_t, std::size_t>> todo{{0, n - 1}};
  while (!todo.empty()) {
    const auto [a, b] = todo.back();
    todo.pop_back();
    double worst = -1;
    std::size_t at = a;
    for (std::size_t i = a + 1; i < b; ++i) {
      const double e = deviation(i, a, b);
      if (e > worst) {
        worst = e;
        at = i;
      }
    }
    if (worst > tolerance) {
      keep[at] = 1;
      todo.emplace_back(a, at);
      todo.emplace_back(at, b);
    }
  }
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i]) kept.push_back(i);
  return kept;
}

}  // namespace tocd::sim::geometry

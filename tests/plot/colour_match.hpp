#pragma once
// Colour comparison shared by the figure tests: a pixel read back from a PNG against the colour
// the figure meant to draw (anti-aliasing and PNG rounding move channels by a few steps).

#include <QColor>
#include <cstdlib>

#include "tocd/plot/figures.hpp"

namespace tocd::plot::testing {

/// Whether every channel of `c` is within `tolerance` of `want`.
inline bool same_colour(QColor c, Rgb want, int tolerance = 3) {
  return std::abs(c.red() - want.r) <= tolerance && std::abs(c.green() - want.g) <= tolerance &&
         std::abs(c.blue() - want.b) <= tolerance;
}

}  // namespace tocd::plot::testing

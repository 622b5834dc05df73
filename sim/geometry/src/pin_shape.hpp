#pragma once

// The glass pin's outline in r-z: a hemispherical tip of radius R (centre on the axis at
// tip + R) and a cylinder of radius R up to the top face. Parameterised by the arc length u
// from the tip.

#include <algorithm>
#include <cmath>
#include <numbers>

#include "section.hpp"

namespace tocd::sim::geometry::detail {

struct PinShape {
  double radius = 1.5, tip_z = 0, top_z = 3.3;

  double centre_z() const { return tip_z + radius; }
  double equator_u() const { return 0.5 * std::numbers::pi * radius; }
  double end_u() const { return equator_u() + (top_z - centre_z()); }

  Vec2 point(double u) const {
    if (u <= equator_u()) {
      const double theta = u / radius;
      return {radius * std::sin(theta), centre_z() - radius * std::cos(theta)};
    }
    return {radius, centre_z() + (u - equator_u())};
  }

  /// Arc parameter of the closest outline point and the signed distance to the outline
  /// (positive outside the pin).
  void project(Vec2 p, double* u, double* distance) const {
    if (p.z <= centre_z()) {
      const double dz = centre_z() - p.z;
      *distance = std::hypot(p.r, dz) - radius;
      *u = radius * std::atan2(p.r, dz);
    } else {
      *distance = p.r - radius;
      *u = std::min(equator_u() + (p.z - centre_z()), end_u());
    }
  }
};

}  // namespace tocd::sim::geometry::detail

#pragma once

#include <Eigen/Core>

namespace tocd::sim::poro {

/// Gap of a point (x, y) to the rigid pin (hemisphere of radius R centred on the axis at
/// height `centre_y`, cylindrical shaft above it): g > 0 outside, the outward unit normal n of
/// the pin surface at the closest point, and the curvature 1 / distance (0 on the shaft).
struct PinGap {
  double gap = 0;
  Eigen::Vector2d normal = Eigen::Vector2d::UnitY();
  double curvature = 0;
};

inline PinGap pin_gap(double x, double y, double radius, double centre_y) {
  PinGap g;
  if (y < centre_y) {
    const Eigen::Vector2d d(x, y - centre_y);
    const double dist = d.norm();
    g.gap = dist - radius;
    g.normal = dist > 0 ? Eigen::Vector2d(d / dist) : Eigen::Vector2d(0, -1);
    g.curvature = dist > 0 ? 1 / dist : 0;
  } else {
    g.gap = x - radius;
    g.normal = Eigen::Vector2d::UnitX();
  }
  return g;
}

}  // namespace tocd::sim::poro

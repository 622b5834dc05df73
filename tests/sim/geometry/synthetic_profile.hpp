#pragma once

// Synthetic pin indentations for the geometry tests: the skin top follows the pin's sphere
// out to a contact radius, then rises exponentially (less steeply than the pin) back to the
// undeformed top; a compressed zone sits under the tip. Sampled like an FE surface.

#include <algorithm>
#include <cmath>
#include <vector>

#include "tocd/sim/geometry/composite.hpp"

namespace tocd::sim::geometry::testing {

struct Indentation {
  double thickness_mm = 2.5;
  double displacement_mm = 1.0;
  double pin_radius_mm = 1.5;
  double spacing_mm = 0.02;  ///< FE-like node spacing along the surface
  double outer_radius_mm = 6.25;
  bool compressed = true;
  bool compressed_on_slide = false;  ///< the zone reaches down to the slide
};

inline double pin_height(const Indentation& in, double r) {
  const double R = in.pin_radius_mm;
  return in.thickness_mm - in.displacement_mm + R - std::sqrt(std::max(0.0, R * R - r * r));
}

inline double contact_radius(const Indentation& in) {
  const double R = in.pin_radius_mm, d = in.displacement_mm;
  return 0.7 * std::sqrt(std::max(0.0, 2 * R * d - d * d));
}

inline double surface_height(const Indentation& in, double r) {
  const double rc = contact_radius(in);
  if (r <= rc) return pin_height(in, r);
  const double R = in.pin_radius_mm;
  const double depth = in.thickness_mm - pin_height(in, rc);
  const double pin_slope = rc / std::sqrt(R * R - rc * rc);
  const double decay = 1.25 * depth / pin_slope;  // skin slope 80 % of the pin's at the edge
  return in.thickness_mm - depth * std::exp(-(r - rc) / decay);
}

inline SkinProfile make_profile(const Indentation& in) {
  SkinProfile p;
  p.thickness_mm = in.thickness_mm;
  const int n = static_cast<int>(std::round(in.outer_radius_mm / in.spacing_mm));
  for (int i = 0; i <= n; ++i) {
    const double r = in.outer_radius_mm * i / n;
    p.top_surface.push_back({r, surface_height(in, r)});
  }
  if (in.compressed && in.displacement_mm > 0) {
    // Under the tip: along the axis, out under the contact, back along the surface.
    const double rj = 0.6 * contact_radius(in);
    const double tip = pin_height(in, 0.0);
    const double bottom = in.compressed_on_slide ? 0.0 : 0.45 * tip;
    std::vector<ProfilePoint> o;
    o.push_back({0.0, bottom});
    o.push_back({0.8 * rj, bottom});
    o.push_back({rj, 0.5 * (bottom + tip)});
    // Surface nodes from r_j back to the axis (the FE's own surface nodes).
    std::vector<ProfilePoint> top;
    for (const auto& q : p.top_surface)
      if (q.r_mm <= rj + 1e-12) top.push_back(q);
    if (top.back().r_mm < rj - 1e-12) top.push_back({rj, surface_height(in, rj)});
    for (auto it = top.rbegin(); it != top.rend(); ++it) o.push_back(*it);
    // Along the axis back down (FE nodes on the axis).
    for (double z = tip - 0.1; z > bottom + 0.05; z -= 0.1) o.push_back({0.0, z});
    p.compressed_outlines.push_back(o);
  }
  return p;
}

inline CompositeSpec make_spec(const Indentation& in) {
  CompositeSpec spec;
  spec.pin_radius_mm = in.pin_radius_mm;
  spec.pin_displacement_mm = in.displacement_mm;
  spec.skin = make_profile(in);
  return spec;
}

}  // namespace tocd::sim::geometry::testing

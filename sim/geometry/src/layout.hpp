#pragma once

// The r-z layout of the composite: the section graph plus everything the 3D complex and the
// volume bookkeeping need (box sizes, flat planes, region seeds, the polygons of each region).

#include <vector>

#include "section.hpp"
#include "tocd/sim/geometry/composite.hpp"

namespace tocd::sim::geometry::detail {

/// Surface ids of the fixed surfaces; compressed outlines follow from kFirstCompressed on.
enum SurfaceId : int {
  kSlideBottom = 0,
  kSlideSides,
  kAirTop,
  kPinTop,
  kSkinSides,
  kAirSides,
  kSlideTop,
  kSkinFlatTop,
  kSkinTop,
  kContact,
  kPinSurface,
  kFirstCompressed
};

/// A horizontal plane of the box (slide top, flat skin top): its facet is the whole square
/// minus holes where no section edge lies on it (inside the revolved part, r < r_core).
struct Plane {
  double z = 0;
  int surface = 0;
};

struct Layout {
  Section section;
  double half_mm = 0;  ///< half the box width
  double slide_thickness_mm = 0;
  double skin_top_mm = 0;  ///< undeformed skin top (0 for the baseline)
  double z_top_mm = 0;     ///< pin top face = air top face
  double r_core_mm = 0;    ///< revolved part of the section: r <= r_core
  bool baseline = false;
  int pin_top_vertex = -1;  ///< (R, z_top)
  std::vector<Plane> planes;
  std::vector<Vec2> pin_polygon;                       ///< closed, for its volume and seed
  std::vector<Vec2> depression_polygon;                ///< skin top vs z = thickness (signed)
  std::vector<std::vector<Vec2>> compressed_polygons;  ///< closed, one per outline
  std::vector<Vec2>
      skin_polygon;  ///< closed: skin top (as meshed) and slide, r <= r_core; empty for the baseline
  double contact_radius_mm = 0;
};

/// Builds and checks the layout of `spec` with section segments of about `section_edge_mm`
/// (which also scales the contact and simplification tolerances), the pin's hemispherical tip
/// and the skin top under it with segments of about `tip_edge_mm` (at most the section edge,
/// as resolve_size gives it).
/// Throws GeometryError naming the surface at fault.
Layout build_layout(const CompositeSpec& spec, double section_edge_mm, double tip_edge_mm);

/// Whether edge e of the section lies in one of the layout's planes (then it is part of that
/// plane's facet, not revolved).
int plane_of_edge(const Layout& layout, const Section::Edge& e);

}  // namespace tocd::sim::geometry::detail

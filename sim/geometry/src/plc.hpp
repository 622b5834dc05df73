#pragma once

// The 3D piecewise-linear complex of one quadrant (x >= 0, y >= 0) of a layout: flat box faces
// plus the revolution of every section edge into N / 4 trapezoids, each given as two triangles
// (one triangle at the axis), the two symmetry planes x = 0 and y = 0 (each the r-z section
// itself), and region seeds. Ring points are perturbed radially within +-5e-10 of their radius
// (plc.cpp). The mesher mirrors the quadrant's mesh across both planes into the whole box.

#include <array>
#include <vector>

#include "layout.hpp"

namespace tocd::sim::geometry::detail {

struct Polygon3 {
  std::vector<int> vertices;
};

struct Facet {
  std::vector<Polygon3> polygons;
  std::vector<std::array<double, 3>> holes;
  int surface = 0;  ///< Section surface id; TetGen's facet marker is surface + 1
};

struct RegionSeed {
  std::array<double, 3> point;
  int region;
};

/// Surface ids of the quadrant's two symmetry planes: no surface of the section, so their
/// faces become interior once the mesh is mirrored (and no boundary marker is given them).
inline constexpr int kSymmetryPlaneX = 1 << 20;              ///< the plane x = 0
inline constexpr int kSymmetryPlaneY = kSymmetryPlaneX + 1;  ///< the plane y = 0

struct Plc {
  std::vector<std::array<double, 3>> points;
  std::vector<Facet> facets;
  std::vector<RegionSeed> seeds;
  /// The complex is the quadrant x >= 0, y >= 0 bounded by the symmetry planes: its mesh is
  /// mirrored across x = 0, then across y = 0.
  bool quadrant = false;
};

/// The quadrant complex; `azimuth_segments` (the whole circle's) must be a multiple of 4, so
/// that both symmetry planes pass through ring points. Throws GeometryError otherwise.
Plc build_plc(const Layout& layout, int azimuth_segments);

}  // namespace tocd::sim::geometry::detail

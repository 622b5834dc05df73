#pragma once

// The 3D piecewise-linear complex of a layout: flat box faces plus the revolution of every
// section edge into N trapezoids, each given as two triangles (one triangle at the axis), with
// region seeds. Ring points are perturbed radially within +-5e-10 of their radius (plc.cpp).

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

struct Plc {
  std::vector<std::array<double, 3>> points;
  std::vector<Facet> facets;
  std::vector<RegionSeed> seeds;
};

Plc build_plc(const Layout& layout, int azimuth_segments);

}  // namespace tocd::sim::geometry::detail

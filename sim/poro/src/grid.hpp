#pragma once

#include <array>
#include <vector>

#include "tocd/sim/poro/model.hpp"

namespace tocd::sim::poro {

/// Structured Taylor-Hood grid on the rectangle: (2 nx + 1) x (2 ny + 1) displacement nodes
/// (corners, mid-sides, centres of the 9-node elements) and (nx + 1) x (ny + 1) pressure nodes
/// (the element corners). Elements are axis-aligned rectangles, numbered row by row.
struct Grid {
  int nx = 0, ny = 0;
  std::vector<double> xs, ys;  ///< displacement-node coordinates along x (2 nx + 1) and y (2 ny + 1)

  int node(int i, int j) const { return j * (2 * nx + 1) + i; }
  int pressure_node(int i, int j) const { return j * (nx + 1) + i; }
  int node_count() const { return (2 * nx + 1) * (2 * ny + 1); }
  int pressure_count() const { return (nx + 1) * (ny + 1); }
  int element_count() const { return nx * ny; }

  /// Local order: node a = 3 lj + li with li, lj in 0..2 along x and y.
  std::array<int, 9> element_nodes(int e) const;
  /// Local order: corner c = 2 lj + li with li, lj in 0..1.
  std::array<int, 4> element_pressure_nodes(int e) const;
  /// Bounds of element e: x0, x1, y0, y1.
  std::array<double, 4> element_box(int e) const;
  /// Element holding reference point (x, y) and its local coordinates in [-1, 1]; -1 outside.
  int locate(double x, double y, double& xi, double& eta) const;
};

Grid make_grid(const RectangleMesh& mesh);

/// Shape functions at local (xi, eta): biquadratic (9) and bilinear (4), with local derivatives.
struct Shape {
  double N9[9], dN9[9][2];
  double N4[4], dN4[4][2];
};
Shape shape_at(double xi, double eta);

}  // namespace tocd::sim::poro

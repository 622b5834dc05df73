#pragma once

#include <vector>

#include "tocd/sim/fe/result.hpp"

namespace tocd::sim::fe {

/// Finds the quad of a (deformed) mesh that contains a point: a uniform bucket grid over the
/// quads' bounding boxes, then an exact point-in-polygon test (edges of bilinear quads stay
/// straight under the deformation).
class PointLocator {
 public:
  explicit PointLocator(const FeMesh& mesh);
  int find(double r_mm, double z_mm) const;  ///< quad index or -1

 private:
  FeMesh mesh_;  // own copy, so results can be copied and moved freely
  double r0_ = 0, z0_ = 0, dr_ = 1, dz_ = 1;
  int nr_ = 1, nz_ = 1;
  std::vector<std::vector<int>> buckets_;
};

}  // namespace tocd::sim::fe

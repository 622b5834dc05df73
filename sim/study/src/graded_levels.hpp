#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "tocd/sim/mesh/topology.hpp"

namespace tocd::sim::study::detail {

/// Splits the skin of `mesh` into graded levels: each skin (or compressed) tet gets the level
/// `level_at(r, z)` gives at its centroid (0: native skin; k > 0: region kGradedRegionBase + k).
/// Returns how many tets each level 0..bins received. The strain-graded and the water-graded
/// optics both split the mesh this way; only what sets the level differs.
std::vector<std::size_t> assign_graded_levels(mesh::TetMesh& mesh, int bins,
                                              const std::function<int(double r, double z)>& level_at);

}  // namespace tocd::sim::study::detail

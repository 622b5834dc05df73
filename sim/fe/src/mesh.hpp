#pragma once

#include <vector>

#include "tocd/sim/fe/model.hpp"
#include "tocd/sim/fe/result.hpp"

namespace tocd::sim::fe {

/// Structured reference mesh of the skin section [0, outer_radius] x [0, thickness]: uniform
/// fine columns out to 1.3 pin radii, geometric growth beyond; rows graded finer toward the top.
FeMesh make_reference_mesh(const FeModel& model);

/// Graded 1D grids (exposed for tests): n cells from 0 to length.
std::vector<double> graded_grid(double length, int cells, double last_over_first);

}  // namespace tocd::sim::fe

#pragma once

#include <Eigen/Core>

#include "assembly.hpp"
#include "tocd/sim/fe/result.hpp"
#include "tocd/sim/material/hyperelastic.hpp"

namespace tocd::sim::fe {

/// Post-processes a converged state: deformed mesh, strains, compressed region, force.
FeStepResult make_step_result(const FeModel& model, const tocd::sim::material::HyperelasticLaw& law,
                              const Assembly& assembly, const Eigen::VectorXd& u, const Evaluation& ev,
                              double displacement_mm);

/// Boundary loops (node indices) of the union of the flagged quads of a structured mesh; the
/// region lies to the left of each loop (outer boundaries counter-clockwise in the reference
/// layout). At a vertex shared by two flagged quads only across a corner the loops are kept apart.
std::vector<std::vector<int>> region_loops(const FeMesh& reference, const std::vector<char>& flagged);

}  // namespace tocd::sim::fe

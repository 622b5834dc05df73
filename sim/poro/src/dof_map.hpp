#pragma once

#include <vector>

#include "grid.hpp"
#include "tocd/sim/poro/model.hpp"

namespace tocd::sim::poro {

/// Global dofs: u_x, u_y of displacement node n at 2n, 2n + 1; pore pressure of pressure node
/// c at 2 node_count + c. Each dof is either fixed (equation -1) or owned by an equation; the
/// top plate's u_y dofs share one equation when the plate is force-driven.
struct DofMap {
  std::vector<int> equation;           ///< per dof
  std::vector<int> plate_dofs;         ///< u_y dofs of the top nodes (plate enabled)
  std::vector<int> drained_pressures;  ///< pressure dofs held at p = 0
  int plate_equation = -1;             ///< shared equation of a force-driven plate
  int equation_count = 0;
  int pressure_offset = 0;
};

/// `sealed_top` (empty, or one flag per top pressure node i = 0..nx): top pressure nodes kept
/// impermeable although the top side is drained (under the pin).
DofMap make_dof_map(const Grid& grid, const PoroModel& model, const std::vector<bool>& sealed_top = {});

}  // namespace tocd::sim::poro

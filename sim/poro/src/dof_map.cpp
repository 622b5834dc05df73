#include "dof_map.hpp"

#include <algorithm>

namespace tocd::sim::poro {

namespace {

enum class SideId { left, right, bottom, top };

bool on_side(SideId s, int i, int j, int last_i, int last_j) {
  switch (s) {
    case SideId::left:
      return i == 0;
    case SideId::right:
      return i == last_i;
    case SideId::bottom:
      return j == 0;
    case SideId::top:
      return j == last_j;
  }
  return false;
}

}  // namespace

DofMap make_dof_map(const Grid& grid, const PoroModel& model, const std::vector<bool>& sealed_top) {
  DofMap m;
  m.pressure_offset = 2 * grid.node_count();
  const int dofs = m.pressure_offset + grid.pressure_count();
  std::vector<bool> fixed(dofs, false);
  const std::pair<SideId, const SideCondition*> sides[4] = {{SideId::left, &model.left},
                                                            {SideId::right, &model.right},
                                                            {SideId::bottom, &model.bottom},
                                                            {SideId::top, &model.top}};
  const int ni = 2 * grid.nx, nj = 2 * grid.ny;
  for (int j = 0; j <= nj; ++j)
    for (int i = 0; i <= ni; ++i) {
      const int n = grid.node(i, j);
      for (const auto& [id, c] : sides) {
        if (!on_side(id, i, j, ni, nj)) continue;
        if (c->fix_x) fixed[2 * n] = true;
        if (c->fix_y) fixed[2 * n + 1] = true;
      }
      if (model.plate.enabled && j == nj && !fixed[2 * n + 1]) m.plate_dofs.push_back(2 * n + 1);
    }
  for (int j = 0; j <= grid.ny; ++j)
    for (int i = 0; i <= grid.nx; ++i)
      for (const auto& [id, c] : sides)
        if (c->drained && on_side(id, i, j, grid.nx, grid.ny)) {
          if (id == SideId::top && !sealed_top.empty() && sealed_top[i]) continue;
          const int dof = m.pressure_offset + grid.pressure_node(i, j);
          if (!fixed[dof]) m.drained_pressures.push_back(dof);
          fixed[dof] = true;
        }
  const bool plate_by_force = model.plate.enabled && !model.plate.displacement_mm;
  m.equation.assign(dofs, -1);
  for (int d = 0; d < dofs; ++d) {
    if (fixed[d]) continue;
    const bool plate = std::find(m.plate_dofs.begin(), m.plate_dofs.end(), d) != m.plate_dofs.end();
    if (plate && !plate_by_force) continue;  // displacement-driven plate: prescribed
    if (plate) {
      if (m.plate_equation < 0) m.plate_equation = m.equation_count++;
      m.equation[d] = m.plate_equation;
    } else {
      m.equation[d] = m.equation_count++;
    }
  }
  return m;
}

}  // namespace tocd::sim::poro

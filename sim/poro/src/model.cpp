#include "tocd/sim/poro/model.hpp"

#include <cmath>

#include <fmt/format.h>

namespace tocd::sim::poro {

void PoroModel::validate() const {
  const auto& m = mesh;
  if (!(m.width_mm > 0) || !(m.height_mm > 0) || !std::isfinite(m.width_mm) || !std::isfinite(m.height_mm))
    throw PoroError(
        fmt::format("mesh width and height must be positive (got {} x {} mm)", m.width_mm, m.height_mm));
  if (m.nx < 1 || m.ny < 1 || m.nx > 2000 || m.ny > 2000)
    throw PoroError(fmt::format("mesh element counts must be 1..2000 (got nx = {}, ny = {})", m.nx, m.ny));
  if (!(m.row_grading > 0) || !std::isfinite(m.row_grading))
    throw PoroError(fmt::format("mesh row_grading must be positive (got {})", m.row_grading));
  try {
    skeleton.validate();
  } catch (const tocd::Error& e) {
    throw PoroError(fmt::format("skeleton material: {}", e.what()));
  }
  if (skeleton.D.empty() || !(skeleton.D[0] > 0))
    throw PoroError("skeleton material needs a bulk modulus (D_1 > 0): the drained skeleton is compressible");
  permeability.validate();
  if (!(pore_closure.onset >= 0 && pore_closure.onset < 1))
    throw PoroError(fmt::format("pore_closure onset must lie in [0, 1) (got {})", pore_closure.onset));
  if (pore_closure.onset > 0 &&
      !(pore_closure.modulus_factor > 0 && std::isfinite(pore_closure.modulus_factor)))
    throw PoroError(fmt::format("pore_closure modulus_factor must be positive and finite (got {})",
                                pore_closure.modulus_factor));
  if (plate.enabled) {
    if (!plate.force_N && !plate.displacement_mm)
      throw PoroError("top plate enabled without a force or a displacement history");
    if (top.fix_y || top.normal_pressure)
      throw PoroError("top plate cannot be combined with fix_y or a normal pressure on the top side");
  }
  if (pin.enabled) {
    if (!pin.displacement_mm) throw PoroError("pin enabled without a displacement history");
    if (!(pin.radius_mm > 0) || !std::isfinite(pin.radius_mm))
      throw PoroError(fmt::format("pin radius must be positive (got {} mm)", pin.radius_mm));
    if (plate.enabled) throw PoroError("pin and top plate cannot both act on the top side");
    if (!left.fix_x) throw PoroError("pin on the axis x = 0: the left side needs fix_x");
    if (!(pin.penalty_factor > 0) || !(pin.penetration_tolerance > 0) || pin.max_augmentations < 0)
      throw PoroError("pin penalty_factor and penetration_tolerance must be positive");
  }
  if (kinematics == Kinematics::axisymmetric && !left.fix_x)
    throw PoroError("axisymmetric model: the left side is the axis and needs fix_x");
  if (solver.max_newton_iterations < 1)
    throw PoroError(
        fmt::format("solver max_newton_iterations must be >= 1 (got {})", solver.max_newton_iterations));
}

}  // namespace tocd::sim::poro

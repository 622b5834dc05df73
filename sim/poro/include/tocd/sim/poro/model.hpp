#pragma once

#include <functional>

#include "tocd/core/error.hpp"
#include "tocd/sim/material/hyperelastic.hpp"
#include "tocd/sim/material/ogden.hpp"

namespace tocd::sim::poro {

/// Bad biphasic model input (names the field and the value found).
using PoroError = tocd::ErrorOf<struct PoroModule>;

/// axisymmetric: x = r (axis at x = 0), volumes and forces for the full revolution;
/// plane_strain: per mm of out-of-plane depth.
enum class Kinematics { axisymmetric, plane_strain };

/// Strain-dependent permeability of Holmes & Mow (1990, J. Biomech. 23:1145), the finite-strain
/// form of Lai & Mow (1980):
///   k(J) = k0 ((J - phi0) / (1 - phi0))^kappa exp(M (J^2 - 1) / 2)
/// with J the volume ratio of the skeleton and phi0 the solid volume fraction at J = 1.
/// k is the hydraulic permeability (Darcy's k / water viscosity) in mm^4/(N s) = mm^2/(MPa s).
struct Permeability {
  double k0_mm4_per_Ns = 1e-3;
  double solid_fraction = 0.2;  ///< phi0 in (0, 1)
  double kappa = 0;             ///< exponent of the porosity factor (>= 0)
  double M = 0;                 ///< exponential stiffening coefficient (>= 0)

  double at(double J) const;          ///< k(J); NaN for J <= phi0 (no pore space left)
  double derivative(double J) const;  ///< dk/dJ
  void validate() const;
};

/// Stiffening of the skeleton as its pores close. The Abaqus volumetric term (J - 1)^2 / D_1
/// alone carries a compressive mean stress of at most K (1 - phi0) before J reaches the solid
/// volume phi0, while the pin's contact pressure reaches several times the shear modulus
/// (measured 4 to 5 mu_0 at 1.0 to 1.25 mm): the element on the axis then compacts to
/// J = phi0, and the time step fails. Real tissue stiffens toward its solid constituents' bulk
/// modulus as the pores close; this term stands in for that with a barrier on the relative
/// pore volume s = (J - phi0) / (1 - phi0): zero with its first two derivatives for
/// s >= onset, growing without bound as s -> 0 (the C2 log barrier of Li et al. 2020,
/// "Incremental Potential Contact", ACM Trans. Graph. 39(4):49, here on the pore volume).
/// Its strength is modulus_factor x the skeleton's small-strain bulk modulus K. With the
/// default 10, a mean pressure of 5 mu_0 (nu = 0.3) leaves about a tenth of the pore volume;
/// with 1 the pores close to about 1 % and Newton, on the steep barrier, failed in the demo's
/// ramp to 1.5 mm (docs/water.md). A stand-in, not a measured law. onset = 0: off.
struct PoreClosure {
  double onset = 0.2;  ///< s below which the term acts, in [0, 1)
  double modulus_factor = 10;

  /// U_c(J) = modulus_factor K b(s), b(s) = -(s - onset)^2 ln(s / onset) for s < onset, and
  /// its first two derivatives in J, for solid fraction phi0 and skeleton bulk modulus K
  /// [MPa]; zero for s >= onset, +inf (with dU = -inf) once the pores are closed (s <= 0).
  tocd::sim::material::VolumetricResponse at(double J, double phi0, double bulk_modulus) const;
};

/// One straight side of the rectangular section.
struct SideCondition {
  bool fix_x = false;    ///< u_x = 0 on the side (symmetry plane, axis, lateral confinement)
  bool fix_y = false;    ///< u_y = 0 on the side
  bool drained = false;  ///< p = 0: water leaves or enters freely; otherwise impermeable
  /// Normal pressure on the side [MPa] at time t [s] (compressive positive), applied on the
  /// undeformed side (dead load); empty: none.
  std::function<double(double)> normal_pressure;
};

/// A rigid, frictionless plate on the top side: every top node moves down together (u_y
/// shared), u_x stays free. Driven either by its total force or by its displacement.
struct TopPlate {
  bool enabled = false;
  /// Total compressive force [N] at time t (axisymmetric: full revolution; plane: per mm of
  /// depth for the modelled section). Used when `displacement_mm` is empty.
  std::function<double(double)> force_N;
  /// Downward displacement [mm] at time t (positive = compression); takes precedence.
  std::function<double(double)> displacement_mm;
};

/// A rigid pin (hemispherical tip of `radius_mm` on a cylindrical shaft of the same radius,
/// on the axis x = 0) pressed into the top side; frictionless augmented-Lagrangian contact on
/// the top nodes. Where the top is drained, the glass seals it from the axis to the contact
/// edge of the previous time step.
struct Pin {
  bool enabled = false;
  double radius_mm = 1.5;
  /// Tip depth below the undeformed top [mm] at time t.
  std::function<double(double)> displacement_mm;
  double penalty_factor = 200;          ///< penalty = factor x mu_0 x nodal ring length (axi)
  double penetration_tolerance = 1e-3;  ///< largest penetration as a fraction of the depth
  int max_augmentations = 8;
};

/// Rectangle [0, width] x [0, height] in elements nx x ny; rows grow geometrically by
/// `row_grading` (ratio of the top row's height to the bottom row's; 1 = uniform).
struct RectangleMesh {
  double width_mm = 1, height_mm = 1;
  int nx = 4, ny = 4;
  double row_grading = 1;
};

struct PoroSolverSettings {
  /// Steps that compact the pores near the pin's axis take 25 to 60 iterations before the
  /// quadratic convergence sets in (the demo's ramp to 1.5 mm); 25 failed there.
  int max_newton_iterations = 60;
  /// Converged when the energy norm |R . du| has dropped by this factor from the first
  /// iteration of the time step.
  double energy_tolerance = 1e-20;
};

struct PoroModel {
  Kinematics kinematics = Kinematics::plane_strain;
  RectangleMesh mesh;
  /// Drained skeleton law (Abaqus-form Ogden; needs a bulk modulus: D_1 > 0).
  tocd::sim::material::OgdenParameters skeleton;
  Permeability permeability;
  PoreClosure pore_closure;
  SideCondition left, right, bottom, top;
  TopPlate plate;
  Pin pin;
  PoroSolverSettings solver;

  /// Throws PoroError naming the bad field.
  void validate() const;
};

}  // namespace tocd::sim::poro

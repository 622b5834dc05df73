#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "tocd/sim/poro/model.hpp"

namespace tocd::sim::poro {

/// The converged state after a time step.
struct PoroState {
  double time_s = 0;
  int newton_iterations = 0;  ///< over all sub-steps of the last advance_to
  /// Times the last advance_to halved a step whose Newton iteration failed (0: one step).
  int step_halvings = 0;
  double plate_displacement_mm = 0;  ///< downward, positive in compression
  double plate_force_N = 0;          ///< compressive force the skeleton + water carry
  /// Water that left through drained sides since t = 0 [mm^3] (the consistent nodal
  /// reactions of the Darcy equation, summed over time steps).
  double water_outflow_mm3 = 0;
  /// Change of the water volume held by the section since t = 0: int (J - 1) dV [mm^3]
  /// (constituents incompressible: the mixture changes volume only by water).
  double water_content_change_mm3 = 0;
  double pin_force_N = 0;            ///< force the pin carries (contact sum)
  double pin_contact_radius_mm = 0;  ///< largest current x of a top node in contact
  double max_penetration_mm = 0;     ///< after the last augmentation
};

/// Biphasic finite-strain FE on a rectangle: Taylor-Hood pair (9-node biquadratic
/// displacement, 4-node bilinear pore pressure), 3x3 Gauss, total stress = Ogden skeleton
/// Kirchhoff stress - J p I, Darcy flow q = -J k(J) C^-1 Grad p, backward Euler in time, full
/// Newton (analytic tangent, SparseLU).
class PoroSolver {
 public:
  explicit PoroSolver(PoroModel model);  ///< validates; state at t = 0 is undeformed, p = 0
  ~PoroSolver();
  PoroSolver(const PoroSolver&) = delete;
  PoroSolver& operator=(const PoroSolver&) = delete;

  /// Advances to `time_s` (> current time) in one backward-Euler step with the loads at that
  /// time; a step whose Newton iteration fails is retried as two half steps, down to 1/1024
  /// of it. Throws PoroError when even that fails (the state is left at the last converged
  /// sub-step).
  const PoroState& advance_to(double time_s);
  const PoroState& state() const;

  /// Fields at a reference point (x, y) inside the section (NaN outside).
  double pressure_at(double x_mm, double y_mm) const;
  Eigen::Vector2d displacement_at(double x_mm, double y_mm) const;
  /// Volume ratio J of the skeleton at a reference point; the water volume fraction there is
  /// 1 - phi0 / J.
  double volume_ratio_at(double x_mm, double y_mm) const;

  const PoroModel& model() const;

  /// Deformed top surface: the current positions of the top nodes, x ascending from 0.
  std::vector<Eigen::Vector2d> top_surface() const;
  /// Reference point whose current position is (x, y); false where (x, y) is outside the
  /// deformed section.
  bool reference_point_of(double x_mm, double y_mm, double& X_mm, double& Y_mm) const;

  /// The element residual and its analytic tangent, exposed so that tests can compare the
  /// tangent with finite differences. Element-local dofs: 9 nodes x (u_x, u_y), then 4 p.
  struct ElementCheck {
    Eigen::VectorXd residual;
    Eigen::MatrixXd tangent;
  };
  ElementCheck element_check(int element, const Eigen::VectorXd& local_dofs,
                             const Eigen::VectorXd& previous_local_dofs, double dt_s) const;
  int element_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tocd::sim::poro

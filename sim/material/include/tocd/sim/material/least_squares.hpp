#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace tocd::sim::material {

/// A nonlinear least-squares problem min sum r_k(theta)^2 whose residuals are expensive (an FE
/// solve per evaluation): the Jacobian is taken by forward differences, one evaluation per
/// parameter. `residuals` returns nullopt where the model cannot be evaluated (a law outside
/// its stable range, an FE solve that stopped); such a trial step is refused like an uphill one.
struct LeastSquaresProblem {
  std::vector<std::string> names;  ///< one per parameter
  Eigen::VectorXd start;
  /// Forward-difference step per parameter (absolute). Large enough to rise above the model's
  /// own numerical noise (an FE force converged to ~1e-6 relative), small against the curvature.
  Eigen::VectorXd difference_step;
  std::function<std::optional<Eigen::VectorXd>(const Eigen::VectorXd&)> residuals;
};

struct LeastSquaresOptions {
  int max_iterations = 40;
  /// Stop when a step lowers the cost by less than this fraction.
  double cost_tolerance = 1e-8;
  double confidence = 0.95;  ///< two-sided level of the reported intervals
  /// Called after each accepted step with (iteration, cost, evaluations so far).
  std::function<void(int, double, int)> progress;
};

struct LeastSquaresResult {
  Eigen::VectorXd theta, residuals;
  Eigen::MatrixXd jacobian;    ///< at theta
  Eigen::MatrixXd covariance;  ///< s^2 (J^T J)^-1 (pseudo-inverse; infinite where unidentified)
  Eigen::VectorXd standard_error, interval_half_width;
  double residual_variance = 0;  ///< s^2 = cost / (points - parameters)
  double cost = 0;               ///< sum of squared residuals
  double t_quantile = 0;         ///< Student t of the interval (points - parameters degrees of freedom)
  int iterations = 0, evaluations = 0;
  bool converged = false;
  std::string stop_reason;  ///< why it stopped ("cost change below tolerance", ...)
};

/// Levenberg-Marquardt (Marquardt's diagonal scaling) with a forward-difference Jacobian,
/// then the linearised covariance of the estimate. Throws MaterialError when the start cannot
/// be evaluated or there are no more points than parameters.
LeastSquaresResult levenberg_marquardt(const LeastSquaresProblem& problem,
                                       const LeastSquaresOptions& options = {});

/// Two-sided Student t quantile: P(|T| <= t) = confidence with `dof` degrees of freedom
/// (Cornish-Fisher expansion around the normal quantile; within 1e-3 relative for dof >= 3).
double student_t_quantile(double confidence, double dof);

}  // namespace tocd::sim::material

#pragma once

// Levenberg-Marquardt on a generalised least-squares cost whose model is costly and noisy (a
// Monte Carlo run per observation): the optics identification's fit (identify_optics.hpp),
// written against a model it calls, so that it is checked on closed forms and a smoother model
// of the same observations can take the Monte Carlo's place.
//
// The cost is (y - m(theta))^T (C + S(theta))^-1 (y - m(theta)): C the data's covariance, S the
// model's own variances at theta. A trial step is kept only when it lowers the cost (plain
// Gauss-Newton steps overshot on the demo run, where mu_a and mu_s trade off at -0.99, and
// wandered off to chi^2 of 170 for 3 degrees of freedom). With a
// Monte Carlo model that comparison is itself noisy: the same seed keeps a photon's path only
// until the changed optics change it, and on the demo run the cost scattered by about 3 between
// neighbouring trials (docs/identify.md), so the minimum found is a lucky draw's. So the fit
// ends, without a trial, with the undamped Gauss-Newton step from a point within reach of the
// minimum: one whose step moves no free parameter by more than a fifth of its standard error.

#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "tocd/analysis/identified.hpp"

namespace tocd::analysis {

/// A model's values at the observations and their standard errors (the model's own noise),
/// with the Jacobian's columns that were asked for (the others zero; the matrix empty when
/// none was asked).
struct GlsEvaluation {
  Eigen::VectorXd value, se;
  Eigen::MatrixXd jacobian;  ///< observations x parameters
  /// A relative error that every value shares, apart from `se`: one draw that scales them all
  /// alike (a Monte Carlo baseline every value is divided by). Independent errors of the same
  /// size would average out over the observations; this one moves them together, and the fit
  /// answers it with a shift of the parameters that mimic a common scale.
  double common_relative_se = 0;
};

/// Evaluates the model at theta; columns[k] says whether column k of the Jacobian is needed
/// (a column costs model runs of its own when it comes from finite differences).
using GlsModel = std::function<GlsEvaluation(const Eigen::VectorXd& theta, const std::vector<bool>& columns)>;

struct GlsProblem {
  Eigen::VectorXd data;
  Eigen::MatrixXd data_covariance;
  /// Every trial is kept inside these: a parameter on its bound that a step pushes out is held
  /// there for that step, and a step that would leave a range is shortened, its direction kept.
  std::vector<PlausibleRange> ranges;
};

struct GlsFitOptions {
  /// Trials (a trial costs one model evaluation without the Jacobian; a kept one an
  /// evaluation with the free parameters' columns).
  int max_iterations = 8;
  /// Called after each trial: its number, theta, cost and whether it was kept.
  std::function<void(int, const Eigen::VectorXd&, double, bool)> on_trial;
  /// Called after the last step, taken without a trial from within reach of the minimum: where
  /// it ended and the cost there.
  std::function<void(const Eigen::VectorXd&, double)> on_last_step;
};

struct GlsFit {
  Eigen::VectorXd theta;
  GlsEvaluation evaluation;  ///< at theta, with the free parameters' columns
  double chi2 = 0;
  int iterations = 0;
  /// The fit ended with the last step from within reach of the minimum (above), or no free
  /// parameter moved by more than a fifth of its standard error in the last kept step (a step a
  /// bound cut short does not count), or every free parameter sits on a bound the step pushes it
  /// against.
  bool converged = false;
};

/// The cost of an evaluation.
double gls_chi2(const GlsProblem& problem, const GlsEvaluation& e);

/// The cost's covariance at an evaluation: C + S, S the model's own variances on its diagonal
/// plus the shared relative error's common part, common_relative_se^2 m m^T.
Eigen::MatrixXd gls_covariance(const GlsProblem& problem, const GlsEvaluation& e);

/// Minimises the cost over the parameters marked free, the others held at their start value.
GlsFit fit_gls(const GlsModel& model, const GlsProblem& problem, const Eigen::VectorXd& start,
               const std::vector<bool>& free, const GlsFitOptions& options = {});

}  // namespace tocd::analysis

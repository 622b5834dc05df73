// Levenberg-Marquardt on a generalised least-squares cost (gls_fit.hpp).
#include "tocd/analysis/gls_fit.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "tocd/core/error.hpp"

namespace tocd::analysis {

namespace {

// Keeps theta a thousandth of each range inside it: the model's own limits (a fraction of 1.0,
// a strain of 0.1) are legal values, but a finite-difference step must not leave the range.
Eigen::VectorXd inside_ranges(Eigen::VectorXd theta, const std::vector<PlausibleRange>& ranges) {
  for (Eigen::Index k = 0; k < theta.size(); ++k) {
    const auto& r = ranges[static_cast<std::size_t>(k)];
    const double margin = 1e-3 * (r.hi - r.lo);
    theta(k) = std::clamp(theta(k), r.lo + margin, r.hi - margin);
  }
  return theta;
}

// The free parameters' indices.
std::vector<Eigen::Index> indices_of(const std::vector<bool>& free) {
  std::vector<Eigen::Index> out;
  for (std::size_t k = 0; k < free.size(); ++k)
    if (free[k]) out.push_back(static_cast<Eigen::Index>(k));
  return out;
}

}  // namespace

Eigen::MatrixXd gls_covariance(const GlsProblem& problem, const GlsEvaluation& e) {
  Eigen::MatrixXd c = problem.data_covariance;
  c.diagonal() += e.se.cwiseProduct(e.se);
  return c;
}

double gls_chi2(const GlsProblem& problem, const GlsEvaluation& e) {
  const Eigen::VectorXd r = problem.data - e.value;
  return r.dot(gls_covariance(problem, e).ldlt().solve(r));
}

GlsFit fit_gls(const GlsModel& model, const GlsProblem& problem, const Eigen::VectorXd& start,
               const std::vector<bool>& free, const GlsFitOptions& options) {
  if (free.size() != static_cast<std::size_t>(start.size()) || problem.ranges.size() != free.size())
    throw Error(fmt::format("a fit of {} parameters with {} free flags and {} ranges", start.size(),
                            free.size(), problem.ranges.size()));
  const std::vector<Eigen::Index> idx = indices_of(free);
  const auto nf = static_cast<Eigen::Index>(idx.size());
  const std::vector<bool> none(free.size(), false);
  GlsFit f;
  f.theta = inside_ranges(start, problem.ranges);
  f.evaluation = model(f.theta, free);
  f.chi2 = gls_chi2(problem, f.evaluation);
  if (nf == 0) return f;
  double lambda = 1e-2;
  int iteration = 1;
  for (; iteration <= options.max_iterations; ++iteration) {
    const Eigen::MatrixXd w = gls_covariance(problem, f.evaluation).inverse();
    Eigen::MatrixXd jf(f.evaluation.jacobian.rows(), nf);
    for (Eigen::Index j = 0; j < nf; ++j)
      jf.col(j) = f.evaluation.jacobian.col(idx[static_cast<std::size_t>(j)]);
    const Eigen::MatrixXd info = jf.transpose() * w * jf;
    const Eigen::VectorXd g = jf.transpose() * w * (problem.data - f.evaluation.value);
    Eigen::MatrixXd damped = info;
    damped.diagonal() += lambda * info.diagonal().cwiseMax(1e-30);
    const Eigen::VectorXd step = damped.ldlt().solve(g);
    Eigen::VectorXd next = f.theta;
    for (Eigen::Index j = 0; j < nf; ++j) next(idx[static_cast<std::size_t>(j)]) += step(j);
    next = inside_ranges(next, problem.ranges);
    const GlsEvaluation trial = model(next, none);
    const double trial_chi2 = gls_chi2(problem, trial);
    const bool kept = trial_chi2 < f.chi2;
    if (options.on_trial) options.on_trial(iteration, next, trial_chi2, kept);
    if (!kept) {
      lambda *= 10;
      continue;
    }
    // Converged when no free parameter moved by more than a fifth of its standard error.
    const Eigen::VectorXd se = info.inverse().diagonal().cwiseMax(0).cwiseSqrt();
    bool small = true;
    for (Eigen::Index j = 0; j < nf; ++j) {
      const Eigen::Index k = idx[static_cast<std::size_t>(j)];
      small = small && std::abs(next(k) - f.theta(k)) <= 0.2 * se(j);
    }
    f.theta = next;
    f.evaluation = model(f.theta, free);
    f.chi2 = gls_chi2(problem, f.evaluation);
    lambda = std::max(lambda / 10, 1e-6);
    if (small) {
      f.converged = true;
      break;
    }
  }
  f.iterations = std::min(iteration, options.max_iterations);
  return f;
}

}  // namespace tocd::analysis

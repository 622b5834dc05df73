// Levenberg-Marquardt on a generalised least-squares cost (gls_fit.hpp).
#include "tocd/analysis/gls_fit.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "tocd/core/error.hpp"

namespace tocd::analysis {

namespace {

// The edges a parameter is kept within: a thousandth of its range inside it. The model's own
// limits (a fraction of 1.0, a strain of 0.1) are legal values, but a finite-difference step
// must not leave the range.
struct Edges {
  double lo, hi;
};

Edges edges_of(const PlausibleRange& r) {
  const double margin = 1e-3 * (r.hi - r.lo);
  return {r.lo + margin, r.hi - margin};
}

Eigen::VectorXd inside_ranges(Eigen::VectorXd theta, const std::vector<PlausibleRange>& ranges) {
  for (Eigen::Index k = 0; k < theta.size(); ++k) {
    const Edges e = edges_of(ranges[static_cast<std::size_t>(k)]);
    theta(k) = std::clamp(theta(k), e.lo, e.hi);
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

// Whether theta(k) sits on the edge inside_ranges keeps it to, at the lower (-1) or the upper
// (+1) end, or neither (0).
int at_bound(const Eigen::VectorXd& theta, Eigen::Index k, const PlausibleRange& r) {
  const Edges e = edges_of(r);
  const double tolerance = 1e-9 * (r.hi - r.lo);
  if (theta(k) <= e.lo + tolerance) return -1;
  if (theta(k) >= e.hi - tolerance) return 1;
  return 0;
}

// The damped Gauss-Newton step over the free parameters (idx), bounded by the ranges: a
// parameter on its bound whose step points out of the range is held there for this step, the
// step solved again without it, and the step is then shortened, its direction kept, to end
// inside the ranges. Clipping each parameter on its own instead broke the step's balance along
// a valley: on the demo run mu_a stopped at its bound while mu_s still took its share of a step
// along their -0.99 valley, and the trial landed off the valley (chi^2 47 to 722 where the kept
// point had 10 to 20): four trials of eight spent so.
struct BoundedStep {
  Eigen::VectorXd step;    ///< over idx
  bool shortened = false;  ///< a bound cut it short: it says nothing of the distance to a minimum
};

BoundedStep bounded_step(const Eigen::MatrixXd& info, const Eigen::VectorXd& g, double lambda,
                         const Eigen::VectorXd& theta, const std::vector<Eigen::Index>& idx,
                         const std::vector<PlausibleRange>& ranges) {
  const auto nf = static_cast<Eigen::Index>(idx.size());
  std::vector<bool> held(idx.size(), false);
  Eigen::VectorXd step = Eigen::VectorXd::Zero(nf);
  for (Eigen::Index round = 0; round <= nf; ++round) {
    std::vector<Eigen::Index> moving;
    for (Eigen::Index j = 0; j < nf; ++j)
      if (!held[static_cast<std::size_t>(j)]) moving.push_back(j);
    step.setZero();
    if (moving.empty()) return {step, false};
    const auto nm = static_cast<Eigen::Index>(moving.size());
    const auto at = [&](Eigen::Index a) { return moving[static_cast<std::size_t>(a)]; };
    Eigen::MatrixXd damped(nm, nm);
    Eigen::VectorXd rhs(nm);
    for (Eigen::Index a = 0; a < nm; ++a) {
      rhs(a) = g(at(a));
      for (Eigen::Index b = 0; b < nm; ++b) damped(a, b) = info(at(a), at(b));
      damped(a, a) += lambda * std::max(info(at(a), at(a)), 1e-30);
    }
    const Eigen::VectorXd sub = damped.ldlt().solve(rhs);
    bool newly_held = false;
    for (Eigen::Index a = 0; a < nm; ++a) {
      const Eigen::Index j = at(a);
      step(j) = sub(a);
      const Eigen::Index k = idx[static_cast<std::size_t>(j)];
      const int side = at_bound(theta, k, ranges[static_cast<std::size_t>(k)]);
      if ((side < 0 && sub(a) < 0) || (side > 0 && sub(a) > 0)) {
        held[static_cast<std::size_t>(j)] = true;
        newly_held = true;
      }
    }
    if (!newly_held) break;
  }
  double scale = 1.0;
  for (Eigen::Index j = 0; j < nf; ++j) {
    const Eigen::Index k = idx[static_cast<std::size_t>(j)];
    const Edges e = edges_of(ranges[static_cast<std::size_t>(k)]);
    const double to = theta(k) + step(j);
    if (to > e.hi) scale = std::min(scale, (e.hi - theta(k)) / step(j));
    if (to < e.lo) scale = std::min(scale, (e.lo - theta(k)) / step(j));
  }
  return {std::max(scale, 0.0) * step, scale < 1.0};
}

// The normal equations of the free parameters at an evaluation: the information J^T W J and
// the gradient J^T W r, with W the inverse of the cost's covariance there, and the free
// parameters' standard errors from the information.
struct Normal {
  Eigen::MatrixXd info;
  Eigen::VectorXd g, se;
};

Normal normal_equations(const GlsProblem& problem, const GlsEvaluation& e,
                        const std::vector<Eigen::Index>& idx) {
  const Eigen::MatrixXd w = gls_covariance(problem, e).inverse();
  Eigen::MatrixXd jf(e.jacobian.rows(), static_cast<Eigen::Index>(idx.size()));
  for (std::size_t j = 0; j < idx.size(); ++j) jf.col(static_cast<Eigen::Index>(j)) = e.jacobian.col(idx[j]);
  Normal n{jf.transpose() * w * jf, jf.transpose() * w * (problem.data - e.value), {}};
  n.se = n.info.inverse().diagonal().cwiseMax(0).cwiseSqrt();
  return n;
}

// Whether every component of a step is within a fifth of its parameter's standard error.
bool within_a_fifth(const Eigen::VectorXd& step, const Eigen::VectorXd& se) {
  for (Eigen::Index j = 0; j < step.size(); ++j)
    if (!(std::abs(step(j)) <= 0.2 * se(j))) return false;
  return true;
}

// The last step, when theta is within reach of the minimum: the undamped Gauss-Newton step from
// it, bounded as every step is, moves no free parameter by more than a fifth of its standard
// error. It is taken without a trial. The quadratic model is exact to second order that near,
// and with a Monte Carlo model a trial's comparison of two noisy costs says only which draw was
// luckier: near the minimum, trials a few thousandths away were refused by the cost's scatter
// alone, and a fit that could converge only on a small kept step ended there unconverged.
// (Reach widened by the step's own Monte Carlo noise was tried: on the demo run the noise is most
// of the standard error, and the fit took its last step after one trial, from chi^2 15.7 to
// 16.5, where the quadratic model no longer held.) Empty when theta is not within reach.
std::optional<Eigen::VectorXd> last_step(const Normal& n, const Eigen::VectorXd& theta,
                                         const std::vector<Eigen::Index>& idx,
                                         const std::vector<PlausibleRange>& ranges) {
  const auto [step, shortened] = bounded_step(n.info, n.g, 0.0, theta, idx, ranges);
  if (shortened || !step.allFinite() || !within_a_fifth(step, n.se)) return std::nullopt;
  Eigen::VectorXd to = theta;
  for (std::size_t j = 0; j < idx.size(); ++j) to(idx[j]) += step(static_cast<Eigen::Index>(j));
  return inside_ranges(to, ranges);
}

}  // namespace

Eigen::MatrixXd gls_covariance(const GlsProblem& problem, const GlsEvaluation& e) {
  Eigen::MatrixXd c = problem.data_covariance;
  c.diagonal() += e.se.cwiseProduct(e.se);
  if (e.common_relative_se > 0)
    c.noalias() += (e.common_relative_se * e.common_relative_se) * e.value * e.value.transpose();
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
  // The last step, from a point within reach of the minimum (last_step).
  const auto finish = [&](const Eigen::VectorXd& to) {
    f.theta = to;
    f.evaluation = model(f.theta, free);
    f.chi2 = gls_chi2(problem, f.evaluation);
    f.converged = true;
    if (options.on_last_step) options.on_last_step(f.theta, f.chi2);
  };
  double lambda = 1e-2;
  int iteration = 1;
  for (; iteration <= options.max_iterations; ++iteration) {
    const Normal n = normal_equations(problem, f.evaluation, idx);
    if (const auto to = last_step(n, f.theta, idx, problem.ranges)) {
      finish(*to);
      break;
    }
    const auto [step, shortened] = bounded_step(n.info, n.g, lambda, f.theta, idx, problem.ranges);
    if (step.isZero(0.0)) {  // every free parameter on a bound it is pushed against: a minimum
      f.converged = true;
      break;
    }
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
    // Converged, too, when the kept step moved no free parameter by more than a fifth of its
    // standard error.
    Eigen::VectorXd moved(nf);
    for (Eigen::Index j = 0; j < nf; ++j) {
      const Eigen::Index k = idx[static_cast<std::size_t>(j)];
      moved(j) = next(k) - f.theta(k);
    }
    const bool small = !shortened && within_a_fifth(moved, n.se);
    f.theta = next;
    f.evaluation = model(f.theta, free);
    f.chi2 = gls_chi2(problem, f.evaluation);
    lambda = std::max(lambda / 10, 1e-6);
    if (small) {
      f.converged = true;
      break;
    }
  }
  // The trials are spent: the last kept point may be within reach of the minimum all the same.
  if (!f.converged)
    if (const auto to = last_step(normal_equations(problem, f.evaluation, idx), f.theta, idx, problem.ranges))
      finish(*to);
  f.iterations = std::min(iteration, options.max_iterations);
  return f;
}

}  // namespace tocd::analysis

#include "tocd/sim/material/fit.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "tocd/core/enum_names.hpp"
#include "tocd/sim/material/hyperelastic.hpp"

namespace tocd::sim::material {

namespace {
constexpr std::array<EnumName<FitModel>, 6> kFitModelNames{{{FitModel::ogden1, "ogden1"},
                                                            {FitModel::ogden2, "ogden2"},
                                                            {FitModel::ogden3, "ogden3"},
                                                            {FitModel::neo_hookean, "neo-hookean"},
                                                            {FitModel::mooney_rivlin, "mooney-rivlin"},
                                                            {FitModel::yeoh, "yeoh"}}};
}  // namespace

FitModel parse_fit_model(const std::string& name) {
  if (const auto m = value_of(kFitModelNames, name)) return *m;
  throw MaterialError(fmt::format("unknown material model '{}' (use {})", name, name_list(kFitModelNames)));
}

std::string to_string(FitModel m) {
  return std::string(name_of(kFitModelNames, m, "?"));
}

double ogden_uniaxial_nominal_stress(const OgdenParameters& p, double lambda) {
  // W(lambda, lambda^-1/2, lambda^-1/2) differentiated: sum (2 mu / alpha)(l^(a-1) - l^(-a/2-1)).
  double P = 0;
  for (std::size_t i = 0; i < p.mu.size(); ++i) {
    const double a = p.alpha[i];
    P += 2 * p.mu[i] / a * (std::pow(lambda, a - 1) - std::pow(lambda, -a / 2 - 1));
  }
  return P;
}

namespace {

using Eigen::VectorXd;

int ogden_terms(FitModel m) {
  switch (m) {
    case FitModel::ogden1:
      return 1;
    case FitModel::ogden2:
      return 2;
    case FitModel::ogden3:
      return 3;
    default:
      return 0;
  }
}

int parameter_count(FitModel m) {
  if (int n = ogden_terms(m)) return 2 * n;
  return m == FitModel::neo_hookean ? 1 : m == FitModel::mooney_rivlin ? 2 : 3;
}

// Ogden form of the parameter vector (Yeoh has none).
OgdenParameters to_ogden(FitModel m, const VectorXd& p) {
  OgdenParameters o;
  if (int n = ogden_terms(m)) {
    for (int i = 0; i < n; ++i) {
      o.mu.push_back(p[2 * i]);
      o.alpha.push_back(p[2 * i + 1]);
    }
  } else if (m == FitModel::neo_hookean) {
    o.mu = {2 * p[0]};
    o.alpha = {2.0};
  } else if (m == FitModel::mooney_rivlin) {
    o.mu = {2 * p[0], 2 * p[1]};
    o.alpha = {2.0, -2.0};
  }
  return o;
}

// Nominal uniaxial stress of the incompressible model at stretch lambda (no allocation: this
// is the inner loop of the fit).
double model_stress(FitModel m, const VectorXd& p, double lambda) {
  auto term = [lambda](double mu, double a) {
    return 2 * mu / a * (std::pow(lambda, a - 1) - std::pow(lambda, -a / 2 - 1));
  };
  switch (m) {
    case FitModel::yeoh: {
      const double e = lambda * lambda + 2 / lambda - 3;
      return 2 * (lambda - 1 / (lambda * lambda)) * (p[0] + 2 * p[1] * e + 3 * p[2] * e * e);
    }
    case FitModel::neo_hookean:
      return term(2 * p[0], 2.0);
    case FitModel::mooney_rivlin:
      return term(2 * p[0], 2.0) + term(2 * p[1], -2.0);
    default: {
      double P = 0;
      for (int i = 0; i < ogden_terms(m); ++i) P += term(p[2 * i], p[2 * i + 1]);
      return P;
    }
  }
}

// The exponents of an Ogden parameter vector (mu_1, alpha_1, mu_2, alpha_2, ...).
VectorXd exponents_of(const VectorXd& p, int terms) {
  VectorXd alpha(terms);
  for (int i = 0; i < terms; ++i) alpha[i] = p[2 * i + 1];
  return alpha;
}

// Smallest difference between two exponents of one Ogden fit (Problem::admissible).
constexpr double kMinExponentGap = 0.1;

struct Problem {
  FitModel model;
  std::vector<double> lambda, target, weight;  // residual_k = weight_k (model - target)
  VectorXd residual(const VectorXd& p) const {
    VectorXd r(lambda.size());
    for (std::size_t k = 0; k < lambda.size(); ++k)
      r[k] = weight[k] * (model_stress(model, p, lambda[k]) - target[k]);
    return r;
  }
  bool admissible(const VectorXd& p) const {
    if (!p.allFinite()) return false;
    return exponents_admissible(exponents_of(p, ogden_terms(model)));
  }
  static bool exponents_admissible(const VectorXd& alpha) {
    for (Eigen::Index i = 0; i < alpha.size(); ++i) {
      if (!std::isfinite(alpha[i]) || std::abs(alpha[i]) < 1e-3 || std::abs(alpha[i]) > 60) return false;
      // Two terms with (nearly) one exponent are one term and its derivative in alpha: huge mus
      // of opposite sign that cancel (mu = +-931 MPa at alphas 4e-5 apart, on exact data of the
      // published law) and fit rounding noise. Keeping the exponents apart keeps the terms
      // distinct, as every published multi-term fit has them.
      for (Eigen::Index j = 0; j < i; ++j)
        if (std::abs(alpha[i] - alpha[j]) < kMinExponentGap) return false;
    }
    return true;
  }
};

struct LmOutcome {
  VectorXd p;
  double cost = std::numeric_limits<double>::infinity();
  int iterations = 0;
  bool converged = false;
};

// Stopping tests as MINPACK's lmder sets them (Moré, Garbow & Hillstrom 1980): the cost and the
// parameters settled to about the square root of the machine precision, or the residual
// orthogonal to every Jacobian column. Tighter tests than these only measure the noise of the
// difference quotients: a fit to exact data then crawls along its valley until the iteration
// limit and reports no convergence at R^2 = 1 - 1e-8.
constexpr double kCostTolerance = 1e-10;     // relative decrease of the cost in one step
constexpr double kStepTolerance = 1.5e-8;    // step relative to the parameters (sqrt of eps)
constexpr double kGradientTolerance = 1e-8;  // cosine of the residual and a Jacobian column

bool first_order_optimal(const Eigen::MatrixXd& J, const VectorXd& r, const VectorXd& g) {
  const double rn = r.norm();
  if (rn == 0) return true;
  for (Eigen::Index j = 0; j < J.cols(); ++j) {
    const double cn = J.col(j).norm();
    if (cn > 0 && std::abs(g[j]) > kGradientTolerance * cn * rn) return false;
  }
  return true;
}

// P: residual(p) -> VectorXd and admissible(p) -> bool.
template <class P>
LmOutcome levenberg_marquardt(const P& pr, VectorXd p, int max_iterations) {
  LmOutcome out;
  if (!pr.admissible(p)) return out;
  VectorXd r = pr.residual(p);
  if (!r.allFinite()) return out;
  double cost = r.squaredNorm(), damping = 1e-3;
  const int n = static_cast<int>(p.size());
  int it = 0;
  for (; it < max_iterations; ++it) {
    Eigen::MatrixXd Jm(r.size(), n);
    for (int j = 0; j < n; ++j) {  // central differences: the models are cheap and smooth
      const double h = 1e-6 * std::max(std::abs(p[j]), 1e-4);
      VectorXd pp = p, pm = p;
      pp[j] += h;
      pm[j] -= h;
      Jm.col(j) = (pr.residual(pp) - pr.residual(pm)) / (2 * h);
    }
    const Eigen::MatrixXd A = Jm.transpose() * Jm;
    const VectorXd g = Jm.transpose() * r;
    if (first_order_optimal(Jm, r, g)) {
      out.converged = true;
      break;
    }
    bool improved = false;
    for (int tries = 0; tries < 30 && !improved; ++tries) {
      Eigen::MatrixXd Ad = A;
      Ad.diagonal() += damping * A.diagonal().cwiseMax(1e-30);  // Marquardt scaling
      const VectorXd step = Ad.ldlt().solve(-g);
      const VectorXd trial = p + step;
      if (pr.admissible(trial)) {
        const VectorXd rt = pr.residual(trial);
        const double ct = rt.squaredNorm();
        if (std::isfinite(ct) && ct < cost) {
          const double rel = (cost - ct) / std::max(cost, 1e-300);
          p = trial;
          r = rt;
          cost = ct;
          damping = std::max(damping / 3, 1e-12);
          improved = true;
          if (rel < kCostTolerance || step.norm() < kStepTolerance * (kStepTolerance + p.norm())) {
            out.converged = true;
          }
          break;
        }
      }
      damping *= 4;
    }
    if (!improved) {
      out.converged = true;  // no descent left at any damping: a (local) minimum
      break;
    }
    if (out.converged) {
      ++it;  // the step that settled it counts
      break;
    }
  }
  out.p = p;
  out.cost = cost;
  out.iterations = std::min(it, max_iterations);
  return out;
}

// Variable projection (Golub & Pereyra 1973) for Ogden models: the mu_i are solved exactly for
// each set of alpha_i and the search runs over the alphas alone. A law with nearly equal
// alphas and large mus of opposite sign (the published skin law: alphas -3.9 ... -4.7, mus
// -0.24 ... +0.12 MPa) is a long curved valley in the 2N parameters, along which a
// Levenberg-Marquardt over all of them crawls for hundreds of iterations; over the N alphas
// the same fit converges in a few dozen.
//
// Each evaluation is the weighted basis at every point, one column per exponent: w_k (2 / a)
// (lambda_k^(a-1) - lambda_k^(-a/2-1)), the stress of a unit mu. The powers are taken as
// exp(x ln lambda_k) on the whole column at once (Eigen vectorises exp; pow, one call at a
// time, was two thirds of a fit's time), and the residual is the basis times the mu it gave:
// the stress is not computed a second time.
struct ProjectedOgden {
  Eigen::ArrayXd log_lambda, weight;
  VectorXd weighted_target;

  explicit ProjectedOgden(const Problem& p)
      : log_lambda(
            Eigen::Map<const Eigen::ArrayXd>(p.lambda.data(), static_cast<Eigen::Index>(p.lambda.size()))
                .log()),
        weight(Eigen::Map<const Eigen::ArrayXd>(p.weight.data(), static_cast<Eigen::Index>(p.weight.size()))),
        weighted_target((weight * Eigen::Map<const Eigen::ArrayXd>(
                                      p.target.data(), static_cast<Eigen::Index>(p.target.size())))
                            .matrix()) {}

  Eigen::MatrixXd basis(const VectorXd& alpha) const {
    Eigen::MatrixXd b(log_lambda.size(), alpha.size());
    for (Eigen::Index j = 0; j < alpha.size(); ++j) {
      const double a = alpha[j];
      b.col(j) =
          (weight * (2 / a) * (((a - 1) * log_lambda).exp() - ((-a / 2 - 1) * log_lambda).exp())).matrix();
    }
    return b;
  }
  // The weighted least-squares mu_i for a basis.
  VectorXd mus(const Eigen::MatrixXd& b) const { return b.colPivHouseholderQr().solve(weighted_target); }
  VectorXd full_parameters(const VectorXd& alpha) const {
    const VectorXd mu = mus(basis(alpha));
    VectorXd p(2 * alpha.size());
    for (Eigen::Index j = 0; j < alpha.size(); ++j) {
      p[2 * j] = mu[j];
      p[2 * j + 1] = alpha[j];
    }
    return p;
  }
  VectorXd residual(const VectorXd& alpha) const {
    const Eigen::MatrixXd b = basis(alpha);
    return b * mus(b) - weighted_target;
  }
  // Non-finite mus make a non-finite residual, which the search rejects as it would here.
  bool admissible(const VectorXd& alpha) const { return Problem::exponents_admissible(alpha); }
};

// Starting points: for Ogden models the mu_i solve a linear least-squares problem once the
// alpha_i are fixed, so each start is a set of alphas with matching mus.
std::vector<VectorXd> starting_points(const Problem& pr) {
  std::vector<VectorXd> starts;
  const int N = ogden_terms(pr.model);
  if (N == 0) {
    // Linear in its coefficients: one linear solve is already the optimum.
    const int n = parameter_count(pr.model);
    Eigen::MatrixXd A(pr.lambda.size(), n);
    for (int j = 0; j < n; ++j) {
      VectorXd e = VectorXd::Zero(n);
      e[j] = 1;
      for (std::size_t k = 0; k < pr.lambda.size(); ++k)
        A(k, j) = pr.weight[k] * model_stress(pr.model, e, pr.lambda[k]);
    }
    VectorXd b(pr.lambda.size());
    for (std::size_t k = 0; k < pr.lambda.size(); ++k) b[k] = pr.weight[k] * pr.target[k];
    starts.push_back(A.colPivHouseholderQr().solve(b));
    return starts;
  }
  const std::vector<double> grid = N < 3 ? std::vector<double>{-12, -8, -5, -3, -1.5, 1.5, 3, 5, 8, 12}
                                         : std::vector<double>{-10, -6, -3, -1.5, 1.5, 3, 6, 10};
  std::vector<int> idx(N);
  const ProjectedOgden projected(pr);
  auto add = [&](const std::vector<double>& alphas) {
    const VectorXd p = projected.full_parameters(
        Eigen::Map<const VectorXd>(alphas.data(), static_cast<Eigen::Index>(alphas.size())));
    if (p.allFinite()) starts.push_back(p);
  };
  const int G = static_cast<int>(grid.size());
  for (int a = 0; a < G; ++a) {
    if (N == 1) {
      add({grid[a]});
      continue;
    }
    for (int b = a + 1; b < G; ++b) {
      if (N == 2) {
        add({grid[a], grid[b]});
        continue;
      }
      for (int c = b + 1; c < G; ++c) add({grid[a], grid[b], grid[c]});
    }
  }
  return starts;
}

// The data as stretches and signed targets, checked, with their relative-residual weights.
Problem fit_problem(const std::vector<double>& strain, const std::vector<double>& stress, FitModel model,
                    const FitOptions& options) {
  if (strain.size() != stress.size())
    throw MaterialError(
        fmt::format("fit: {} strain values but {} stress values", strain.size(), stress.size()));
  const int n = parameter_count(model);
  if (static_cast<int>(strain.size()) < n + 1)
    throw MaterialError(
        fmt::format("fit: {} needs at least {} data points, got {}", to_string(model), n + 1, strain.size()));
  if (!(options.poisson_ratio > -1.0 && options.poisson_ratio <= 0.5))
    throw MaterialError(fmt::format("fit: Poisson's ratio {} outside (-1, 0.5]", options.poisson_ratio));
  Problem pr;
  pr.model = model;
  double smax = 0;
  for (std::size_t k = 0; k < strain.size(); ++k) {
    const double e = strain[k], s = stress[k];
    if (!std::isfinite(e) || !std::isfinite(s))
      throw MaterialError(fmt::format("fit: data point {} is not finite", k + 1));
    if (options.compression && (e < 0 || e >= 1))
      throw MaterialError(fmt::format(
          "fit: compression strain {} at point {} outside [0, 1) (give magnitudes: displacement / thickness)",
          e, k + 1));
    if (!options.compression && (e <= -1 || e >= 10))
      throw MaterialError(fmt::format("fit: nominal strain {} at point {} outside (-1, 10)", e, k + 1));
    pr.lambda.push_back(options.compression ? 1 - e : 1 + e);
    pr.target.push_back(options.compression ? -s : s);
    smax = std::max(smax, std::abs(s));
  }
  if (!(smax > 0)) throw MaterialError("fit: every stress value is zero");
  // Relative residuals (as Abaqus fits test data), with a floor so near-zero points do not dominate.
  for (double t : pr.target) pr.weight.push_back(1.0 / std::max(std::abs(t), 1e-2 * smax));
  return pr;
}

// Above this many points an Ogden fit screens its starting points on a subsample (every
// stride-th point, about kScreenPoints of them) and polishes the kPolished best on all the data.
// The starts only pick the basin; a smooth curve sampled at 2,000 points ranks them as it does
// at 20,000, and the polish finds the same minimum at a tenth of the cost (20,000 points: 20 s
// without the screen; bench/material).
constexpr std::size_t kScreenPoints = 2000;
constexpr int kPolished = 4;

Problem subsample(const Problem& pr, std::size_t stride) {
  Problem sub;
  sub.model = pr.model;
  for (std::size_t k = 0; k < pr.lambda.size(); k += stride) {
    sub.lambda.push_back(pr.lambda[k]);
    sub.target.push_back(pr.target[k]);
    sub.weight.push_back(pr.weight[k]);
  }
  return sub;
}

// Levenberg-Marquardt over an Ogden fit's exponents from each start (the mu solved exactly for
// each set of alphas), every outcome in the starts' order. The runs are independent (the
// projection holds no state), so they are shared out over the cores; each outcome is the same
// whichever core ran it, and the best is picked in the starts' order: the fit does not depend
// on the number of cores.
std::vector<LmOutcome> ogden_runs(const Problem& pr, const std::vector<VectorXd>& alphas,
                                  int max_iterations) {
  const ProjectedOgden projected(pr);
  std::vector<LmOutcome> out(alphas.size());
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i = next++; i < alphas.size(); i = next++) {
      LmOutcome o = levenberg_marquardt(projected, alphas[i], max_iterations);
      if (std::isfinite(o.cost)) o.p = projected.full_parameters(o.p);
      out[i] = std::move(o);
    }
  };
  const std::size_t cores = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> helpers;
  for (std::size_t t = 1; t < std::min(cores, alphas.size()); ++t) helpers.emplace_back(work);
  work();
  for (auto& h : helpers) h.join();
  return out;
}

// The best of Levenberg-Marquardt runs from every starting point.
LmOutcome best_fit(const Problem& pr, const FitOptions& options) {
  LmOutcome best;
  const int N = ogden_terms(pr.model);
  const std::vector<VectorXd> starts = starting_points(pr);
  if (N == 0) {
    for (const VectorXd& p0 : starts) {
      LmOutcome o = levenberg_marquardt(pr, p0, options.max_iterations);
      if (o.cost < best.cost) best = o;
    }
  } else {
    std::vector<VectorXd> alphas;
    for (const VectorXd& p0 : starts) alphas.push_back(exponents_of(p0, N));
    if (pr.lambda.size() > kScreenPoints) {
      // Screen on the subsample; polish its best few (by cost, then by start order) on all.
      const std::size_t stride = (pr.lambda.size() + kScreenPoints - 1) / kScreenPoints;
      std::vector<LmOutcome> screened = ogden_runs(subsample(pr, stride), alphas, options.max_iterations);
      std::vector<std::size_t> order(screened.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::stable_sort(order.begin(), order.end(),
                       [&](std::size_t a, std::size_t b) { return screened[a].cost < screened[b].cost; });
      std::vector<VectorXd> polish;
      for (std::size_t i = 0; i < order.size() && polish.size() < static_cast<std::size_t>(kPolished); ++i) {
        const LmOutcome& o = screened[order[i]];
        if (!std::isfinite(o.cost)) break;
        polish.push_back(exponents_of(o.p, N));
      }
      alphas = polish;
    }
    for (LmOutcome& o : ogden_runs(pr, alphas, options.max_iterations))
      if (o.cost < best.cost) best = std::move(o);
  }
  if (!std::isfinite(best.cost))
    throw MaterialError(fmt::format("fit: {} found no admissible parameters", to_string(pr.model)));
  return best;
}

std::vector<std::string> parameter_names(FitModel model) {
  const int N = ogden_terms(model);
  std::vector<std::string> names;
  if (N > 0) {
    for (int i = 0; i < N; ++i) {
      names.push_back(fmt::format("mu{}", i + 1));
      names.push_back(fmt::format("alpha{}", i + 1));
    }
  } else if (model == FitModel::neo_hookean) {
    names = {"C10"};
  } else if (model == FitModel::mooney_rivlin) {
    names = {"C10", "C01"};
  } else {
    names = {"C10", "C20", "C30"};
  }
  return names;
}

// The fitted stresses, their residuals and the goodness of fit.
void add_residuals(FitResult& res, const Problem& pr, const VectorXd& p, const std::vector<double>& stress,
                   bool compression) {
  double ss_res = 0, ss_tot = 0, mean = 0;
  for (double s : stress) mean += s;
  mean /= static_cast<double>(stress.size());
  for (std::size_t k = 0; k < stress.size(); ++k) {
    const double m = model_stress(pr.model, p, pr.lambda[k]);
    const double fitted = compression ? -m : m;
    res.fitted_stress.push_back(fitted);
    res.residuals.push_back(fitted - stress[k]);
    ss_res += (fitted - stress[k]) * (fitted - stress[k]);
    ss_tot += (stress[k] - mean) * (stress[k] - mean);
    res.max_abs_residual_MPa = std::max(res.max_abs_residual_MPa, std::abs(fitted - stress[k]));
  }
  res.rms_MPa = std::sqrt(ss_res / static_cast<double>(stress.size()));
  res.r_squared = ss_tot > 0 ? 1 - ss_res / ss_tot : 1.0;
}

}  // namespace

FitResult fit_uniaxial(const std::vector<double>& strain, const std::vector<double>& stress, FitModel model,
                       const FitOptions& options) {
  const Problem pr = fit_problem(strain, stress, model, options);
  const LmOutcome best = best_fit(pr, options);
  FitResult res;
  res.model = model;
  res.iterations = best.iterations;
  res.converged = best.converged;
  res.values.assign(best.p.data(), best.p.data() + best.p.size());
  res.names = parameter_names(model);
  const double mu0 =
      model == FitModel::yeoh ? 2 * best.p[0] : to_ogden(model, best.p).initial_shear_modulus();
  const double nu = options.poisson_ratio;
  const double D1 = nu >= 0.5 ? 0.0 : 3 * (1 - 2 * nu) / (mu0 * (1 + nu));  // = 2 / K0
  res.D = {D1};
  res.has_ogden_form = model != FitModel::yeoh;
  if (res.has_ogden_form) {
    res.ogden = to_ogden(model, best.p);
    res.ogden.D = {D1};
  }
  add_residuals(res, pr, best.p, stress, options.compression);
  const auto [lo, hi] = std::minmax_element(pr.lambda.begin(), pr.lambda.end());
  const double lmin = std::min(*lo, 1 / *hi), lmax = std::max(*hi, 1 / *lo);
  if (mu0 > 0) {
    std::unique_ptr<HyperelasticLaw> law =
        model == FitModel::yeoh ? make_yeoh(best.p[0], best.p[1], best.p[2], 0.0) : make_ogden(res.ogden);
    res.stability = check_stability(*law, lmin, lmax);
  } else {
    res.stability.stable = false;
    res.stability.lambda_min = lmin;
    res.stability.lambda_max = lmax;
    res.stability.first_failure = fmt::format("initial shear modulus {} MPa is not positive", mu0);
  }
  return res;
}

}  // namespace tocd::sim::material

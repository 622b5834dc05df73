// QLV mechanics of a recorded run (identify_mechanics.hpp).
#include "tocd/analysis/identify_mechanics.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <tuple>

#include <fmt/format.h>

#include "tocd/core/error.hpp"
#include "tocd/sim/fe/model.hpp"
#include "tocd/sim/fe/solve.hpp"
#include "tocd/sim/material/qlv.hpp"

namespace tocd::analysis {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Ranges a pin-compression run of skin could give before it is seen (identified.hpp).
constexpr PlausibleRange kOffsetRange{-1.0, 1.0, false};   // N: a load cell tared off the sample
constexpr PlausibleRange kScaleRange{0.1, 10.0, true};     // x the published law
constexpr PlausibleRange kFractionRange{0.0, 2.0, false};  // overstress per unit load increment
constexpr PlausibleRange kTauRange{0.1, 1000.0, true};     // s

// Piecewise-linear elastic response through (0, 0) and the given points, extended by its last
// slope beyond the deepest point (a pin that overshoots a little).
class ElasticResponse {
 public:
  ElasticResponse(std::vector<double> d, std::vector<double> f) : d_(std::move(d)), f_(std::move(f)) {}
  double operator()(double d) const {
    if (d <= 0) return 0.0;
    if (d >= d_.back()) {
      const std::size_t n = d_.size();
      const double slope = (f_[n - 1] - f_[n - 2]) / (d_[n - 1] - d_[n - 2]);
      return f_.back() + slope * (d - d_.back());
    }
    return interpolate(d_, f_, d);
  }

 private:
  std::vector<double> d_, f_;
};

// The least-squares problem: readings of the holds against the QLV model, natural parameters
// p = (c, s, g_1, tau_1, ..., g_K, tau_K).
struct Problem {
  const RunHistory& h;
  std::vector<double> elastic;    // F_e at every tester reading
  std::vector<std::size_t> rows;  // readings in the holds
  int terms = 1;

  Eigen::Index parameters() const { return 2 + 2 * terms; }

  // Model at the rows and (when asked) its Jacobian in natural parameters.
  Eigen::VectorXd model(const Eigen::VectorXd& p, Eigen::MatrixXd* jacobian) const {
    const double c = p(0), s = p(1);
    std::vector<double> total = elastic;  // F_e + sum g_i h_i at every reading
    std::vector<std::vector<double>> hist(static_cast<std::size_t>(terms)),
        dhist(static_cast<std::size_t>(terms));
    for (int i = 0; i < terms; ++i) {
      const auto k = static_cast<std::size_t>(i);
      hist[k] =
          sim::material::prony_history(h.tester_t_s, elastic, p(3 + 2 * i), jacobian ? &dhist[k] : nullptr);
      for (std::size_t n = 0; n < total.size(); ++n) total[n] += p(2 + 2 * i) * hist[k][n];
    }
    Eigen::VectorXd f(static_cast<Eigen::Index>(rows.size()));
    if (jacobian) jacobian->resize(f.size(), parameters());
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const std::size_t n = rows[r];
      const auto row = static_cast<Eigen::Index>(r);
      f(row) = c + s * total[n];
      if (!jacobian) continue;
      (*jacobian)(row, 0) = 1.0;
      (*jacobian)(row, 1) = total[n];
      for (int i = 0; i < terms; ++i) {
        const auto k = static_cast<std::size_t>(i);
        (*jacobian)(row, 2 + 2 * i) = s * hist[k][n];
        (*jacobian)(row, 3 + 2 * i) = s * p(2 + 2 * i) * dhist[k][n];
      }
    }
    return f;
  }

  Eigen::VectorXd observed() const {
    Eigen::VectorXd y(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t r = 0; r < rows.size(); ++r) y(static_cast<Eigen::Index>(r)) = h.load_N[rows[r]];
    return y;
  }
};

// One Prony term, tau fixed: the model is linear in (c, s, s g). Returns the residual sum of
// squares and the natural parameters.
double linear_fit(const Problem& pr, const Eigen::VectorXd& y, double tau, Eigen::VectorXd& p) {
  const auto hist = sim::material::prony_history(pr.h.tester_t_s, pr.elastic, tau);
  Eigen::MatrixXd a(y.size(), 3);
  for (std::size_t r = 0; r < pr.rows.size(); ++r) {
    const auto row = static_cast<Eigen::Index>(r);
    a(row, 0) = 1.0;
    a(row, 1) = pr.elastic[pr.rows[r]];
    a(row, 2) = hist[pr.rows[r]];
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(y);
  p.resize(4);
  p << x(0), x(1), x(1) != 0 ? x(2) / x(1) : 0.0, tau;
  return (y - a * x).squaredNorm();
}

// Start of the search: the best single term on a log grid of tau from 0.1 s to five times the
// run's length (variable projection: the linear parameters solved exactly at every tau); K > 1
// terms spread around it by factors of 5 with the overstress shared out.
Eigen::VectorXd starting_point(const Problem& pr, const Eigen::VectorXd& y) {
  const double span = std::max(1.0, pr.h.tester_t_s.back() - pr.h.tester_t_s.front());
  Eigen::VectorXd best;
  double best_cost = std::numeric_limits<double>::infinity();
  constexpr int grid = 40;
  for (int k = 0; k < grid; ++k) {
    const double tau = 0.1 * std::pow(50.0 * span, static_cast<double>(k) / (grid - 1));
    Eigen::VectorXd p;
    const double cost = linear_fit(pr, y, tau, p);
    if (cost < best_cost && p(2) >= 0) {
      best_cost = cost;
      best = p;
    }
  }
  if (best.size() == 0) {  // no grid point gave g >= 0: start from a small overstress
    best.resize(4);
    best << 0.0, 1.0, 0.1, span / 4;
  }
  Eigen::VectorXd p(pr.parameters());
  p(0) = best(0);
  p(1) = best(1);
  for (int i = 0; i < pr.terms; ++i) {
    p(2 + 2 * i) = std::max(best(2), 0.01) / pr.terms;
    p(3 + 2 * i) = best(3) * std::pow(5.0, i - 0.5 * (pr.terms - 1));
  }
  return p;
}

// Levenberg-Marquardt in (c, s, g_i, ln tau_i): tau stays positive. Stops when a step changes
// no parameter by more than 1e-9 of its size and the cost by less than 1e-12 of itself. A
// `fixed` parameter (its index, for a profile) keeps its starting value. A fit that has not
// stopped after kLmIterations reports itself not converged.
constexpr int kLmIterations = 300;
struct LmOutcome {
  Eigen::VectorXd p;
  int iterations = 0;
  bool converged = false;
};
LmOutcome levenberg_marquardt(const Problem& pr, const Eigen::VectorXd& y, Eigen::VectorXd p,
                              Eigen::Index fixed = -1) {
  auto to_search = [&](const Eigen::VectorXd& nat) {
    Eigen::VectorXd q = nat;
    for (int i = 0; i < pr.terms; ++i) q(3 + 2 * i) = std::log(nat(3 + 2 * i));
    return q;
  };
  auto to_natural = [&](const Eigen::VectorXd& q) {
    Eigen::VectorXd nat = q;
    for (int i = 0; i < pr.terms; ++i) nat(3 + 2 * i) = std::exp(q(3 + 2 * i));
    return nat;
  };
  Eigen::VectorXd q = to_search(p);
  double lambda = 1e-3;
  LmOutcome out;
  Eigen::MatrixXd j;
  Eigen::VectorXd r = y - pr.model(p, &j);
  double cost = r.squaredNorm();
  for (out.iterations = 1; out.iterations <= kLmIterations; ++out.iterations) {
    for (int i = 0; i < pr.terms; ++i) j.col(3 + 2 * i) *= p(3 + 2 * i);  // d/d ln tau
    if (fixed >= 0) j.col(fixed).setZero();
    Eigen::MatrixXd a = j.transpose() * j;
    const Eigen::VectorXd b = j.transpose() * r;
    if (fixed >= 0) a(fixed, fixed) = 1.0;  // its step solves to zero
    bool improved = false;
    for (int attempt = 0; attempt < 30 && !improved; ++attempt) {
      Eigen::MatrixXd damped = a;
      damped.diagonal() += lambda * a.diagonal().cwiseMax(1e-30);
      const Eigen::VectorXd step = damped.ldlt().solve(b);
      const Eigen::VectorXd q_new = q + step;
      const Eigen::VectorXd p_new = to_natural(q_new);
      bool usable = p_new.allFinite();
      for (int i = 0; i < pr.terms; ++i)  // a time the QLV recursion can take (1 us .. 3 years)
        usable = usable && p_new(3 + 2 * i) > 1e-6 && p_new(3 + 2 * i) < 1e8;
      if (!usable) {
        lambda *= 10;
        continue;
      }
      Eigen::MatrixXd j_new;
      const Eigen::VectorXd r_new = y - pr.model(p_new, &j_new);
      const double cost_new = r_new.squaredNorm();
      if (cost_new <= cost) {
        const bool small_step =
            (step.array().abs() <= 1e-9 * (q.array().abs() + 1e-9)).all() || cost - cost_new <= 1e-12 * cost;
        q = q_new;
        p = p_new;
        r = r_new;
        j = j_new;
        cost = cost_new;
        lambda = std::max(lambda / 3, 1e-12);
        improved = true;
        if (small_step) {
          out.converged = true;
          out.p = p;
          return out;
        }
      } else {
        lambda *= 4;
      }
    }
    if (!improved) {  // no step lowers the cost: at a minimum to round-off
      out.converged = true;
      break;
    }
  }
  out.p = p;
  out.iterations = std::min(out.iterations, kLmIterations);  // the loop's counter ends one past when spent
  return out;
}

// Profile intervals of every parameter the covariance sees (identified.hpp): each value held
// while Levenberg-Marquardt refits the others, warm-started from the last point on the same
// side. With holds shorter than the relaxation, stiffness, overstress share and relaxation time
// lie in a curved valley (correlations beyond 0.99) whose Wald intervals undercover.
void profile_intervals(const Problem& pr, const Eigen::VectorXd& y, const Eigen::VectorXd& best,
                       double residual_variance, ParameterReport& rep) {
  const double rss_min = (y - pr.model(best, nullptr)).squaredNorm();
  for (Eigen::Index k = 0; k < pr.parameters(); ++k) {
    auto& param = rep.parameters[static_cast<std::size_t>(k)];
    if (!std::isfinite(param.se)) continue;
    Eigen::VectorXd warm = best;
    bool above = true;  // the side of the estimate the last profile point was on
    auto refit_from = [&](Eigen::VectorXd start, double v) {
      start(k) = v;
      const LmOutcome fit = levenberg_marquardt(pr, y, start, k);
      return std::pair{fit.p, (y - pr.model(fit.p, nullptr)).squaredNorm()};
    };
    apply_profile(param, [&](double v) {
      if ((v > best(k)) != above) warm = best;  // a new side: from the estimate
      above = v > best(k);
      auto [p, cost] = refit_from(warm, v);
      // The last point's fit may lie far out: the walk's first step can overshoot the crossing
      // several-fold, and a refit there can end in a corner (g near 0, tau at its cap) from which
      // the next points never come back. Their rises then stayed huge and the interval's end
      // collapsed onto the estimate (7 of 30 closed-form runs with tau = 35 s and 7 s holds).
      // So each point is also refitted from the estimate, and the lower cost is kept.
      if (warm != best) {
        auto [q, from_best] = refit_from(best, v);
        if (from_best < cost) std::tie(p, cost) = std::tie(q, from_best);
      }
      warm = p;
      return (cost - rss_min) / residual_variance;
    });
  }
}

std::vector<double> held_displacements(const RunHistory& h) {
  std::vector<double> d;
  for (const auto& hold : h.holds)
    if (hold.displacement_mm > 1e-4) d.push_back(hold.displacement_mm);
  std::sort(d.begin(), d.end());
  std::vector<double> distinct;
  for (double x : d)
    if (distinct.empty() || x - distinct.back() > 1e-4) distinct.push_back(x);
  return distinct;
}

}  // namespace

MechanicsIdentification identify_mechanics(const RunHistory& history, const MechanicsOptions& options) {
  const auto displacements = held_displacements(history);
  if (displacements.size() < 2)
    throw Error(fmt::format("run {}: {} held displacement(s) in contact; the mechanics need at least two",
                            history.run_id, displacements.size()));
  auto say = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  sim::fe::FeModel model = sim::fe::FeModel::published_default();
  model.thickness_mm = history.thickness_mm;
  model.pin_radius_mm = options.pin_radius_mm;
  say(fmt::format("FE of the published law, {} mm thick, at {} held displacements to {:.3f} mm",
                  history.thickness_mm, displacements.size(), displacements.back()));
  const auto t0 = Clock::now();
  const sim::fe::FeResult fe = sim::fe::solve(model, displacements);
  if (!fe.complete || fe.steps.size() != displacements.size())
    throw Error(fmt::format("run {}: the FE stopped before the deepest held displacement ({})",
                            history.run_id, fe.stop_reason));
  std::vector<double> d{0.0}, f{0.0};
  for (const auto& s : fe.steps) {
    d.push_back(s.displacement_mm);
    f.push_back(s.force_N);
  }
  auto result = identify_mechanics(history, d, f, options);
  result.fe_seconds = seconds_since(t0) - result.fit_seconds;
  return result;
}

MechanicsIdentification identify_mechanics(const RunHistory& history, const std::vector<double>& elastic_d_mm,
                                           const std::vector<double>& elastic_load_N,
                                           const MechanicsOptions& options) {
  if (options.prony_terms < 1 || options.prony_terms > 3)
    throw ConfigError(fmt::format("Prony terms: {} (expected 1 to 3)", options.prony_terms));
  if (elastic_d_mm.size() != elastic_load_N.size() || elastic_d_mm.size() < 2)
    throw Error("the elastic response needs at least two (displacement, load) points");
  const auto t0 = Clock::now();
  const ElasticResponse response(elastic_d_mm, elastic_load_N);
  Problem pr{history, {}, {}, options.prony_terms};
  pr.elastic.reserve(history.displacement_mm.size());
  for (double d : history.displacement_mm) pr.elastic.push_back(response(d));
  std::vector<std::pair<std::size_t, std::size_t>> segments;
  for (const auto& hold : history.holds) {
    segments.emplace_back(pr.rows.size(), pr.rows.size() + (hold.last - hold.first));
    for (std::size_t n = hold.first; n <= hold.last; ++n) pr.rows.push_back(n);
  }
  if (pr.rows.size() <= static_cast<std::size_t>(pr.parameters()) + 1)
    throw Error(fmt::format("run {}: {} readings in the holds for {} parameters", history.run_id,
                            pr.rows.size(), pr.parameters()));
  if (options.progress)
    options.progress(fmt::format("QLV fit with {} Prony term(s) to {} readings in {} holds", pr.terms,
                                 pr.rows.size(), history.holds.size()));

  const Eigen::VectorXd y = pr.observed();
  const LmOutcome lm = levenberg_marquardt(pr, y, starting_point(pr, y));
  Eigen::MatrixXd j;
  const Eigen::VectorXd fitted = pr.model(lm.p, &j);
  const Eigen::VectorXd r = y - fitted;

  MechanicsIdentification out;
  out.thickness_mm = history.thickness_mm;
  out.fe_displacement_mm = elastic_d_mm;
  out.fe_load_N = elastic_load_N;
  auto& rep = out.report;
  rep.observations = pr.rows.size();
  rep.iterations = lm.iterations;
  rep.converged = lm.converged;
  const auto dof = static_cast<double>(pr.rows.size()) - static_cast<double>(pr.parameters());
  const double sigma2 = r.squaredNorm() / dof;
  rep.noise_sigma = std::sqrt(sigma2);
  rep.residual_rms = std::sqrt(r.squaredNorm() / static_cast<double>(pr.rows.size()));
  set_autocorrelation(rep, r, segments);
  rep.parameters.push_back({"load_offset_N", "load the cell reads with no sample load (after its tare)",
                            lm.p(0), 0, 0, 0, kOffsetRange, false, ""});
  rep.parameters.push_back({"stiffness_scale", "shear moduli of the published Ogden skin law times this",
                            lm.p(1), 0, 0, 0, kScaleRange, false, ""});
  for (int i = 0; i < pr.terms; ++i) {
    rep.parameters.push_back(
        {fmt::format("g{}", i + 1),
         fmt::format("Prony term {}: overstress per unit of equilibrium load increment", i + 1),
         lm.p(2 + 2 * i), 0, 0, 0, kFractionRange, false, ""});
    rep.parameters.push_back({fmt::format("tau{}_s", i + 1),
                              fmt::format("Prony term {}: relaxation time", i + 1), lm.p(3 + 2 * i), 0, 0, 0,
                              kTauRange, false, ""});
  }
  apply_covariance(rep, least_squares_covariance(j, sigma2 * rep.variance_inflation));
  // A fit that ran out of iterations stopped at a point that is not the cost's minimum: its
  // intervals, from the covariance or profiled from there, say nothing. One closed-form run with
  // a 35 s relaxation behind 7 s holds drifted along its valley to g 10.1 (the plausible range
  // ends at 2) and reported tau1_s "determined", 130 s [38, 148], for a truth of 35 s.
  if (lm.converged)
    profile_intervals(pr, y, lm.p, sigma2 * rep.variance_inflation, rep);
  else
    withhold_determination(
        rep, fmt::format("the fit did not converge in {} iterations: its estimate is not the cost's minimum",
                         lm.iterations));

  std::size_t row = 0;
  for (const auto& hold : history.holds) {
    HoldLoad hl;
    hl.step_index = hold.step_index;
    hl.displacement_mm = hold.displacement_mm;
    hl.elastic_N = response(hold.displacement_mm);
    double measured = 0, model = 0, sq = 0;
    std::size_t count = 0;
    for (std::size_t n = hold.first; n <= hold.last; ++n, ++row) {
      sq += r(static_cast<Eigen::Index>(row)) * r(static_cast<Eigen::Index>(row));
      if (n < hold.record_first) continue;
      measured += y(static_cast<Eigen::Index>(row));
      model += fitted(static_cast<Eigen::Index>(row));
      ++count;
    }
    hl.measured_N = count ? measured / static_cast<double>(count) : std::nan("");
    hl.fitted_N = count ? model / static_cast<double>(count) : std::nan("");
    hl.residual_rms_N = std::sqrt(sq / static_cast<double>(hold.last - hold.first + 1));
    out.holds.push_back(hl);
  }
  out.fit_seconds = seconds_since(t0);
  return out;
}

nlohmann::json to_json(const MechanicsIdentification& m) {
  nlohmann::json holds = nlohmann::json::array();
  for (const auto& h : m.holds)
    holds.push_back({{"step", h.step_index + 1},
                     {"displacement_mm", h.displacement_mm},
                     {"elastic_load_published_N", h.elastic_N},
                     {"measured_load_N", h.measured_N},
                     {"fitted_load_N", h.fitted_N},
                     {"residual_rms_N", h.residual_rms_N}});
  nlohmann::json j = to_json(m.report);
  j["model"] = "QLV: F = c + s [F_e(d) + sum g_i h_i], F_e the FE of the published Ogden skin law";
  j["thickness_mm"] = m.thickness_mm;
  j["holds"] = holds;
  j["fe"] = {{"displacement_mm", m.fe_displacement_mm}, {"load_N", m.fe_load_N}, {"seconds", m.fe_seconds}};
  j["fit_seconds"] = m.fit_seconds;
  return j;
}

}  // namespace tocd::analysis

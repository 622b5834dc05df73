// Intervals, determination and correlations of identified parameters (identified.hpp).
#include "tocd/analysis/identified.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "tocd/core/error.hpp"

namespace tocd::analysis {

const IdentifiedParameter& ParameterReport::at(const std::string& name) const {
  for (const auto& p : parameters)
    if (p.name == name) return p;
  throw Error(fmt::format("no identified parameter named {}", name));
}

Eigen::MatrixXd least_squares_covariance(const Eigen::MatrixXd& jacobian, double sigma2) {
  const auto n = jacobian.cols();
  Eigen::VectorXd scale(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double norm = jacobian.col(j).norm();
    scale(j) = norm > 0 ? 1.0 / norm : 0.0;
  }
  const Eigen::MatrixXd js = jacobian * scale.asDiagonal();
  const Eigen::MatrixXd info = js.transpose() * js;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(info);
  const Eigen::VectorXd lambda = eig.eigenvalues();
  const Eigen::MatrixXd v = eig.eigenvectors();
  const double largest = lambda.maxCoeff();
  Eigen::MatrixXd inv = Eigen::MatrixXd::Zero(n, n);
  std::vector<bool> blind(static_cast<std::size_t>(n), false);
  for (Eigen::Index k = 0; k < n; ++k) {
    if (lambda(k) > 1e-12 * largest) {
      inv += v.col(k) * v.col(k).transpose() / lambda(k);
    } else {
      // A direction the data do not see: every parameter with a share in it is unknown.
      for (Eigen::Index j = 0; j < n; ++j)
        if (std::abs(v(j, k)) > 1e-3) blind[static_cast<std::size_t>(j)] = true;
    }
  }
  Eigen::MatrixXd cov = sigma2 * scale.asDiagonal() * inv * scale.asDiagonal();
  for (Eigen::Index j = 0; j < n; ++j)
    if (blind[static_cast<std::size_t>(j)] || scale(j) == 0)
      cov(j, j) = std::numeric_limits<double>::infinity();
  return cov;
}

namespace {

double lag1_autocorrelation(const Eigen::VectorXd& r,
                            const std::vector<std::pair<std::size_t, std::size_t>>& segments) {
  double num = 0, den = 0;
  for (const auto& [first, last] : segments) {
    for (auto k = static_cast<Eigen::Index>(first); k <= static_cast<Eigen::Index>(last) && k < r.size();
         ++k) {
      den += r(k) * r(k);
      if (k > static_cast<Eigen::Index>(first)) num += r(k) * r(k - 1);
    }
  }
  return den > 0 ? num / den : 0.0;
}

}  // namespace

void set_autocorrelation(ParameterReport& report, const Eigen::VectorXd& residuals,
                         const std::vector<std::pair<std::size_t, std::size_t>>& segments) {
  report.autocorrelation = lag1_autocorrelation(residuals, segments);
  report.variance_inflation =
      report.autocorrelation > 0 ? (1 + report.autocorrelation) / (1 - report.autocorrelation) : 1.0;
}

namespace {

// Where a parameter's value lives for its interval: ln for log-scale parameters.
struct Axis {
  bool log = false;
  double to_u(double v) const { return log ? std::log(v) : v; }
  double to_v(double u) const { return log ? std::exp(u) : u; }
};

Axis axis_of(const IdentifiedParameter& p) {
  return Axis{p.range.log_scale && p.value > 0 && p.range.lo > 0};
}

// The determination rule (PlausibleRange) on the parameter's interval; an end left open (the
// profile did not reach it inside the plausible range) leaves it undetermined.
void judge(IdentifiedParameter& p, const char* open_side = nullptr) {
  const Axis ax = axis_of(p);
  const double width = (ax.to_u(p.hi) - ax.to_u(p.lo)) / (ax.to_u(p.range.hi) - ax.to_u(p.range.lo));
  // An interval the run leaves open on one side is a bound, not a value, however narrow the
  // plausible range makes it look (a delayed clearing of 8 % gave tau_w "394 s [199, 1000]":
  // 1000 is the range's end, not something the run said).
  p.determined = width < 0.25 && !open_side;
  if (p.determined)
    p.why_not.clear();
  else if (open_side)
    p.why_not = fmt::format("the run does not bound it {} inside the plausible range {:g} .. {:g}", open_side,
                            p.range.lo, p.range.hi);
  else
    p.why_not = fmt::format("its 95 % interval spans {:.0f} % of the plausible range {:g} .. {:g}",
                            100 * width, p.range.lo, p.range.hi);
}

// One end of a profile interval (apply_profile): where sqrt(rise) reaches z on side `dir`, or
// nothing when the profile stays below it out to the plausible range's end.
std::optional<double> profile_end(const IdentifiedParameter& p, const CostRise& rise, double z, int dir) {
  const Axis ax = axis_of(p);
  const double u0 = ax.to_u(p.value);
  const double edge = ax.to_u(dir > 0 ? p.range.hi : p.range.lo);
  if (!(dir * (edge - u0) > 0)) return std::nullopt;
  auto g = [&](double u) {
    const double r = rise(ax.to_v(u));
    return std::isfinite(r) ? std::sqrt(std::max(r, 0.0)) - z : std::numeric_limits<double>::quiet_NaN();
  };
  const double se_u = ax.log ? p.se / p.value : p.se;
  double step = std::isfinite(se_u) && se_u > 0 ? z * se_u : 0.05 * std::abs(edge - u0);
  step = std::min(step, std::abs(edge - u0));
  double ua = u0, ga = -z;
  double ub = u0 + dir * step, gb = g(ub);
  // Walk out by secant steps (each between a quarter and four times the last) until the
  // crossing is bracketed; sqrt(rise) is close to linear near the estimate.
  for (int evals = 1; !(gb >= 0); ++evals) {
    if (std::isnan(gb) || ub == edge || evals > 40) return std::nullopt;
    const double last = std::abs(ub - ua);
    double delta = gb > ga ? (ub - ua) * (-gb) / (gb - ga) : 2 * (ub - ua);
    delta = dir * std::clamp(std::abs(delta), 0.25 * last, 4 * last);
    double next = ub + delta;
    if (dir * (next - edge) > 0) next = edge;
    ua = ub;
    ga = gb;
    ub = next;
    gb = g(ub);
  }
  // Regula falsi with the Illinois halving (an end kept twice running has its value halved),
  // to sqrt(rise) within 1e-3 of z.
  int last_moved = 0;  // +1: ub moved last, -1: ua moved last
  if (gb < 1e-3) return ax.to_v(ub);
  for (int it = 0; it < 60; ++it) {
    if (std::abs(ub - ua) < 1e-10 * (1 + std::abs(u0))) break;
    const double m = ub - gb * (ub - ua) / (gb - ga);
    const double gm = g(m);
    if (std::isnan(gm)) return std::nullopt;
    if (std::abs(gm) < 1e-3) return ax.to_v(m);
    if (gm >= 0) {
      ub = m;
      gb = gm;
      if (last_moved == +1) ga *= 0.5;
      last_moved = +1;
    } else {
      ua = m;
      ga = gm;
      if (last_moved == -1) gb *= 0.5;
      last_moved = -1;
    }
  }
  return ax.to_v(0.5 * (ua + ub));
}

}  // namespace

void apply_profile(IdentifiedParameter& p, const CostRise& rise, double z) {
  const auto lo = profile_end(p, rise, z, -1);
  const auto hi = profile_end(p, rise, z, +1);
  p.interval = "profile";
  p.lo = lo ? *lo : p.range.lo;
  p.hi = hi ? *hi : p.range.hi;
  judge(p, !lo && !hi ? "on either side" : !lo ? "below" : !hi ? "above" : nullptr);
}

void widen_to_profile_hull(IdentifiedParameter& p, const std::vector<std::pair<double, double>>& scan,
                           double z) {
  const double threshold = z * z, lo = p.lo, hi = p.hi;
  bool open_lo = lo <= p.range.lo, open_hi = hi >= p.range.hi, widened = false;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const auto& [value, rise] = scan[i];
    if (!(rise < threshold) || (value >= lo && value <= hi)) continue;
    widened = true;
    if (value < lo) {
      // The first such point below the interval sets its new end, one grid value further.
      const double end = i == 0 ? p.range.lo : scan[i - 1].first;
      open_lo = open_lo || i == 0;
      p.lo = std::min(p.lo, end);
    } else {
      const double end = i + 1 == scan.size() ? p.range.hi : scan[i + 1].first;
      open_hi = open_hi || i + 1 == scan.size();
      p.hi = std::max(p.hi, end);
    }
  }
  if (!widened) return;
  judge(p, open_lo && open_hi ? "on either side" : open_lo ? "below" : open_hi ? "above" : nullptr);
}

void widen_over_valley(IdentifiedParameter& p, std::size_t index, const std::vector<ValleyPoint>& valley,
                       double rss_min, double residual_variance, double z) {
  if (!std::isfinite(p.se)) return;
  const double budget = z * z * residual_variance;
  bool widened = false;
  for (const auto& point : valley) {
    const double spare = budget - (point.cost - rss_min);
    const double variance = point.conditional_variance[index];
    if (!(spare > 0) || !(variance > 0) || !std::isfinite(variance)) continue;
    const double half = std::sqrt(spare * variance);
    const double lo = point.linear[index] - half, hi = point.linear[index] + half;
    if (lo >= p.lo && hi <= p.hi) continue;
    p.lo = std::min(p.lo, std::max(lo, p.range.lo));
    p.hi = std::max(p.hi, std::min(hi, p.range.hi));
    widened = true;
  }
  if (!widened) return;
  p.interval = "profile";
  judge(p);
}

void withhold_determination(ParameterReport& report, const std::string& why) {
  for (auto& p : report.parameters) {
    if (!p.determined) continue;
    p.determined = false;
    p.why_not = why;
  }
}

void apply_covariance(ParameterReport& report, const Eigen::MatrixXd& cov, double z) {
  const auto n = static_cast<Eigen::Index>(report.parameters.size());
  if (cov.rows() != n || cov.cols() != n)
    throw Error(fmt::format("covariance of {} parameters for a report of {}", cov.rows(), n));
  report.correlation.assign(static_cast<std::size_t>(n),
                            std::vector<double>(static_cast<std::size_t>(n), 0.0));
  for (Eigen::Index i = 0; i < n; ++i) {
    auto& p = report.parameters[static_cast<std::size_t>(i)];
    const double var = cov(i, i);
    p.se = std::isfinite(var) && var > 0 ? std::sqrt(var) : std::numeric_limits<double>::infinity();
    if (!std::isfinite(p.se)) {
      p.lo = -std::numeric_limits<double>::infinity();
      p.hi = std::numeric_limits<double>::infinity();
      p.determined = false;
      p.why_not =
          "the run carries no information on it (its column of the Jacobian is zero or "
          "a combination of the others)";
    } else {
      if (p.range.log_scale && p.value > 0) {
        const double s = p.se / p.value;
        p.lo = p.value * std::exp(-z * s);
        p.hi = p.value * std::exp(z * s);
      } else {
        p.lo = p.value - z * p.se;
        p.hi = p.value + z * p.se;
      }
      p.interval = "wald";
      judge(p);
    }
    for (Eigen::Index j = 0; j < n; ++j) {
      const double c = cov(i, j) / std::sqrt(cov(i, i) * cov(j, j));
      report.correlation[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
          i == j ? 1.0 : (std::isfinite(c) ? c : 0.0);
    }
  }
}

nlohmann::json to_json(const ParameterReport& report) {
  nlohmann::json params = nlohmann::json::array();
  auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  for (const auto& p : report.parameters) {
    nlohmann::json j = {{"name", p.name},
                        {"description", p.description},
                        {"value", p.value},
                        {"se", number(p.se)},
                        {"ci95", {number(p.lo), number(p.hi)}},
                        {"interval", p.interval},
                        {"plausible_range", {p.range.lo, p.range.hi}},
                        {"determined", p.determined}};
    if (!p.determined) j["why_not_determined"] = p.why_not;
    params.push_back(j);
  }
  nlohmann::json names = nlohmann::json::array();
  for (const auto& p : report.parameters) names.push_back(p.name);
  return {{"parameters", params},
          {"correlation", {{"names", names}, {"matrix", report.correlation}}},
          {"residual_rms", report.residual_rms},
          {"noise_sigma", report.noise_sigma},
          {"residual_autocorrelation", report.autocorrelation},
          {"variance_inflation", report.variance_inflation},
          {"observations", report.observations},
          {"iterations", report.iterations},
          {"converged", report.converged}};
}

}  // namespace tocd::analysis

#include "tocd/sim/fe/inverse_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "tocd/core/enum_names.hpp"
#include "tocd/sim/fe/solve.hpp"
#include "tocd/sim/material/hyperelastic.hpp"
#include "tocd/sim/material/least_squares.hpp"
#include "tocd/sim/material/stiffness_scale.hpp"

namespace tocd::sim::fe {

namespace mat = tocd::sim::material;
using Eigen::VectorXd;

namespace {
constexpr std::array<EnumName<InverseModel>, 4> kInverseModelNames{{{InverseModel::scaled, "scaled"},
                                                                    {InverseModel::ogden1, "ogden1"},
                                                                    {InverseModel::ogden2, "ogden2"},
                                                                    {InverseModel::ogden3, "ogden3"}}};
}  // namespace

InverseModel parse_inverse_model(const std::string& name) {
  if (const auto m = value_of(kInverseModelNames, name)) return *m;
  throw mat::MaterialError(
      fmt::format("unknown model '{}' for the FE fit (use {})", name, name_list(kInverseModelNames)));
}

std::string to_string(InverseModel m) {
  return std::string(name_of(kInverseModelNames, m, "?"));
}

std::vector<double> pin_force_curve(const PinCompressionData& data, const mat::OgdenParameters& material) {
  FeModel m = data.model;
  m.material = material;
  const FeResult r = solve(m, data.displacement_mm);
  if (!r.complete || r.steps.size() != data.displacement_mm.size()) return {};
  std::vector<double> f;
  for (const auto& s : r.steps) f.push_back(s.force_N);
  return f;
}

namespace {

int ogden_terms(InverseModel m) {
  return m == InverseModel::ogden1 ? 1 : m == InverseModel::ogden2 ? 2 : m == InverseModel::ogden3 ? 3 : 0;
}

}  // namespace

std::size_t free_parameters(InverseModel m, bool fit_D) {
  const int n = ogden_terms(m);
  return n == 0 ? 1 : static_cast<std::size_t>(2 * n + (fit_D ? 1 : 0));
}

namespace {

double poisson_D1(double mu0, double nu) {
  return 3 * (1 - 2 * nu) / (mu0 * (1 + nu));  // D_1 = 2 / K_0, K_0 = 2 mu_0 (1 + nu) / (3 (1 - 2 nu))
}

void check_data(const std::vector<PinCompressionData>& pins, const std::vector<ClosedFormData>& closed) {
  if (pins.empty() && closed.empty()) throw mat::MaterialError("material fit: no datasets given");
  for (const auto& p : pins) {
    if (p.displacement_mm.size() != p.load_N.size() || p.displacement_mm.empty())
      throw mat::MaterialError(fmt::format("{}: {} displacements but {} loads", p.name,
                                           p.displacement_mm.size(), p.load_N.size()));
    double last = 0;
    for (std::size_t k = 0; k < p.displacement_mm.size(); ++k) {
      const double d = p.displacement_mm[k];
      if (!std::isfinite(p.load_N[k]) || !(d > last) || !(d < p.model.thickness_mm))
        throw mat::MaterialError(fmt::format(
            "{}: point {} (displacement {} mm, load {} N): displacements must ascend in (0, {}) mm and "
            "loads be numbers",
            p.name, k + 1, d, p.load_N[k], p.model.thickness_mm));
      last = d;
    }
    if (!(p.weight > 0)) throw mat::MaterialError(fmt::format("{}: weight {} must be > 0", p.name, p.weight));
  }
  for (const auto& c : closed) {
    if (c.x.size() != c.stress_MPa.size() || c.x.empty())
      throw mat::MaterialError(
          fmt::format("{}: {} stretches but {} stresses", c.name, c.x.size(), c.stress_MPa.size()));
    for (std::size_t k = 0; k < c.x.size(); ++k)
      if (!std::isfinite(c.x[k]) || !std::isfinite(c.stress_MPa[k]) ||
          (c.mode != mat::LoadingMode::simple_shear && !(c.x[k] > 0)))
        throw mat::MaterialError(fmt::format("{}: point {} ({}, {} MPa) is not a valid {} point", c.name,
                                             k + 1, c.x[k], c.stress_MPa[k], mat::to_string(c.mode)));
    if (!(c.weight > 0)) throw mat::MaterialError(fmt::format("{}: weight {} must be > 0", c.name, c.weight));
  }
}

double largest_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

// Model values of every dataset for one law: FE curves, then closed forms. nullopt when the
// law is inadmissible or an FE solve stops.
struct Evaluator {
  const std::vector<PinCompressionData>& pins;
  const std::vector<ClosedFormData>& closed;
  std::optional<std::vector<std::vector<double>>> operator()(const mat::OgdenParameters& law) const {
    try {
      law.validate();
      for (double a : law.alpha)
        if (std::abs(a) < 1e-2 || std::abs(a) > 60) return std::nullopt;
      std::vector<std::vector<double>> out;
      for (const auto& p : pins) {
        out.push_back(pin_force_curve(p, law));
        if (out.back().size() != p.load_N.size()) return std::nullopt;
      }
      for (const auto& c : closed) {
        std::vector<double> s;
        for (double x : c.x) s.push_back(mat::ogden_nominal_stress(law, c.mode, x));
        out.push_back(std::move(s));
      }
      return out;
    } catch (const tocd::ConfigError&) {  // FeError (Drucker refusal), MaterialError
      return std::nullopt;
    }
  }
};

struct Weighted {
  std::vector<const std::vector<double>*> data;
  std::vector<double> floor, sqrt_weight;
  VectorXd residuals(const std::vector<std::vector<double>>& model) const {
    std::size_t n = 0;
    for (const auto* d : data) n += d->size();
    VectorXd r(static_cast<Eigen::Index>(n));
    Eigen::Index k = 0;
    for (std::size_t s = 0; s < data.size(); ++s)
      for (std::size_t i = 0; i < data[s]->size(); ++i) {
        const double m = (*data[s])[i];
        r[k++] = sqrt_weight[s] * (model[s][i] - m) / std::max(std::abs(m), floor[s]);
      }
    return r;
  }
};

// One material fit: the datasets, their weights and the reference law, with the steps of the
// fit as methods.
struct MaterialFit {
  const std::vector<PinCompressionData>& pins;
  const std::vector<ClosedFormData>& closed;
  const InverseFitOptions& o;
  Evaluator eval{pins, closed};
  Weighted w;
  mat::OgdenParameters ref = o.reference;
  int N = ogden_terms(o.model);

  MaterialFit(const std::vector<PinCompressionData>& p, const std::vector<ClosedFormData>& c,
              const InverseFitOptions& opt)
      : pins(p), closed(c), o(opt) {
    for (const auto& pin : pins) {
      w.data.push_back(&pin.load_N);
      w.floor.push_back(std::max(o.relative_floor * largest_abs(pin.load_N), 1e-300));
      w.sqrt_weight.push_back(std::sqrt(pin.weight));
    }
    for (const auto& cf : closed) {
      w.data.push_back(&cf.stress_MPa);
      w.floor.push_back(std::max(o.relative_floor * largest_abs(cf.stress_MPa), 1e-300));
      w.sqrt_weight.push_back(std::sqrt(cf.weight));
    }
    if (ref.D.empty() || ref.D[0] == 0.0) ref.D = {poisson_D1(ref.initial_shear_modulus(), o.poisson_ratio)};
  }

  void say(const std::string& s) const {
    if (o.progress) o.progress(s);
  }

  // Every model value scales exactly with a common factor on the energy (displacement control:
  // same deformation, forces x s), so the best factor for a law's shape is linear least
  // squares from one evaluation. Returns (factor, cost), or nullopt if the shape cannot be solved.
  std::optional<std::pair<double, double>> best_scale(const mat::OgdenParameters& shape) const {
    const auto values = eval(shape);
    if (!values) return std::nullopt;
    const VectorXd r = w.residuals(*values);  // sqrt(w)(m - d)/f
    std::vector<std::vector<double>> zero = *values;
    for (auto& v : zero) std::fill(v.begin(), v.end(), 0.0);
    const VectorXd minus_d = w.residuals(zero);  // -sqrt(w) d / f
    const VectorXd m = r - minus_d;              // sqrt(w) m / f
    const double num = -m.dot(minus_d), den = m.squaredNorm();
    const double f = den > 0 && num > 0 ? num / den : 1.0;
    return std::make_pair(f, (f * m + minus_d).squaredNorm());
  }

  // The reference law scaled by s0, or, for another number of terms, the best of candidate
  // shapes (stable, mu_i > 0: the one or two-term Ogden closest to the reference's uniaxial
  // curve, and a few alphas), each scaled to the data.
  mat::OgdenParameters starting_law(double s0) const {
    mat::OgdenParameters start = mat::scale_stiffness(ref, s0);
    if (N == 0 || static_cast<int>(start.mu.size()) == N) return start;
    std::vector<mat::OgdenParameters> shapes;
    const double mu0 = ref.initial_shear_modulus();
    try {
      std::vector<double> strain, stress;
      for (int k = 0; k < 30; ++k) {
        const double lam = 0.35 + 0.6 * k / 30.0;  // compression, where the data are
        strain.push_back(lam - 1);
        stress.push_back(mat::ogden_uniaxial_nominal_stress(ref, lam));
      }
      mat::FitOptions fo;
      fo.compression = false;
      fo.poisson_ratio = o.poisson_ratio;
      const auto f =
          mat::fit_uniaxial(strain, stress, N == 1 ? mat::FitModel::ogden1 : mat::FitModel::ogden2, fo);
      if (f.stability.stable) shapes.push_back(f.ogden);
    } catch (const mat::MaterialError&) {
    }
    if (N == 1) {
      for (double a : {-6.0, -4.0, -2.0, 2.0, 4.0}) shapes.push_back({{mu0}, {a}, {}});
    } else {
      for (auto [a1, a2] : {std::pair{-6.0, 2.0}, std::pair{-4.0, 4.0}, std::pair{-2.0, 2.0}})
        shapes.push_back({{mu0 / 2, mu0 / 2}, {a1, a2}, {}});
    }
    double best = std::numeric_limits<double>::infinity();
    for (auto shape : shapes) {
      shape.D = {poisson_D1(shape.initial_shear_modulus(), o.poisson_ratio)};
      const auto fit = best_scale(shape);
      if (fit && fit->second < best) {
        best = fit->second;
        start = mat::scale_stiffness(shape, fit->first);
      }
    }
    if (!std::isfinite(best)) throw FeError("material fit: no starting law the FE can solve");
    say(fmt::format("start: mu {} alpha {}", fmt::join(start.mu, ", "), fmt::join(start.alpha, ", ")));
    return start;
  }

  // The law of a parameter vector: the reference's scale (N = 0), or the Ogden terms (and D1).
  mat::OgdenParameters to_law(const VectorXd& t) const {
    if (N == 0) return mat::scale_stiffness(ref, t[0]);
    mat::OgdenParameters p;
    for (int i = 0; i < N; ++i) {
      p.mu.push_back(t[2 * i]);
      p.alpha.push_back(t[2 * i + 1]);
    }
    const double mu0 = p.initial_shear_modulus();
    p.D = {o.fit_D ? t[2 * N] : (mu0 > 0 ? poisson_D1(mu0, o.poisson_ratio) : -1.0)};
    return p;
  }

  mat::LeastSquaresProblem problem(const mat::OgdenParameters& start, double s0) const {
    mat::LeastSquaresProblem pr;
    if (N == 0) {
      pr.names = {"s"};
      pr.start = VectorXd::Constant(1, s0);
      pr.difference_step = VectorXd::Constant(1, 1e-3 * s0);
    } else {
      pr.start.resize(2 * N + (o.fit_D ? 1 : 0));
      pr.difference_step.resize(pr.start.size());
      const double mu0 = start.initial_shear_modulus();
      for (int i = 0; i < N; ++i) {
        pr.names.push_back(fmt::format("mu{}", i + 1));
        pr.names.push_back(fmt::format("alpha{}", i + 1));
        pr.start[2 * i] = start.mu[i];
        pr.start[2 * i + 1] = start.alpha[i];
        // 1e-3 relative: the FE force is converged to ~1e-6 relative, so the difference quotient
        // keeps ~3 digits, more than the curvature error of a step this small.
        pr.difference_step[2 * i] = 1e-3 * std::max(std::abs(start.mu[i]), 0.1 * std::abs(mu0));
        pr.difference_step[2 * i + 1] = 1e-3 * std::max(std::abs(start.alpha[i]), 0.5);
      }
      if (o.fit_D) {
        pr.names.push_back("D1");
        pr.start[2 * N] = poisson_D1(mu0, o.poisson_ratio);
        pr.difference_step[2 * N] = 1e-3 * pr.start[2 * N];
      }
    }
    pr.residuals = [this](const VectorXd& t) -> std::optional<VectorXd> {
      const auto v = eval(to_law(t));
      if (!v) return std::nullopt;
      return w.residuals(*v);
    };
    return pr;
  }

  // The laws at both ends of each axis of the confidence ellipsoid that are admissible.
  void add_confidence_laws(InverseFitResult& out, const mat::LeastSquaresResult& ls) const {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(ls.covariance);
    for (Eigen::Index k = 0; es.info() == Eigen::Success && k < ls.theta.size(); ++k) {
      const double l = es.eigenvalues()[k];
      if (!std::isfinite(l) || !(l > 0)) continue;
      for (int sign : {-1, 1}) {
        const VectorXd t = ls.theta + sign * ls.t_quantile * std::sqrt(l) * es.eigenvectors().col(k);
        mat::OgdenParameters law = to_law(t);
        try {
          law.validate();
        } catch (const mat::MaterialError&) {
          continue;  // an axis end outside the admissible laws (e.g. mu_0 <= 0)
        }
        out.confidence_laws.emplace_back(fmt::format("axis {} {}", k + 1, sign < 0 ? '-' : '+'), law);
      }
    }
  }

  // Each dataset measured beside the fitted law's values.
  void add_datasets(InverseFitResult& out) const {
    const auto fitted = eval(out.material);
    if (!fitted) throw FeError("material fit: the fitted law cannot be re-evaluated");  // accepted above
    for (std::size_t s = 0; s < w.data.size(); ++s) {
      DatasetFit d;
      const bool pin = s < pins.size();
      d.name = pin ? pins[s].name : closed[s - pins.size()].name;
      d.x = pin ? pins[s].displacement_mm : closed[s - pins.size()].x;
      d.measured = *w.data[s];
      d.fitted = (*fitted)[s];
      double sum = 0;
      for (std::size_t i = 0; i < d.measured.size(); ++i) {
        const double rel = (d.fitted[i] - d.measured[i]) / std::max(std::abs(d.measured[i]), w.floor[s]);
        sum += rel * rel;
        d.max_abs_relative = std::max(d.max_abs_relative, std::abs(rel));
      }
      d.rms_relative = std::sqrt(sum / static_cast<double>(d.measured.size()));
      out.datasets.push_back(std::move(d));
    }
  }
};

void add_estimates(InverseFitResult& out, const mat::LeastSquaresResult& ls) {
  out.residual_variance = ls.residual_variance;
  out.t_quantile = ls.t_quantile;
  out.iterations = ls.iterations;
  out.evaluations = ls.evaluations;
  out.converged = ls.converged;
  out.stop_reason = ls.stop_reason;
  for (Eigen::Index j = 0; j < ls.theta.size(); ++j) {
    out.values.push_back(ls.theta[j]);
    out.standard_errors.push_back(ls.standard_error[j]);
    out.interval_low.push_back(ls.theta[j] - ls.interval_half_width[j]);
    out.interval_high.push_back(ls.theta[j] + ls.interval_half_width[j]);
    std::vector<double> row;
    for (Eigen::Index k = 0; k < ls.theta.size(); ++k) row.push_back(ls.covariance(j, k));
    out.covariance.push_back(std::move(row));
  }
}

// Stability: the wide range first; if it fails, the stable interval around 1 by bisection.
void add_stability(InverseFitResult& out) {
  const auto law = mat::make_ogden(out.material);
  out.stability = mat::check_stability(*law, 0.15, 1 / 0.15);
  out.stable_lambda_min = 0.15;
  out.stable_lambda_max = 1 / 0.15;
  if (out.stability.stable) return;
  auto bisect = [&](double unstable, bool below) {
    double stable = 1.0;
    for (int k = 0; k < 30; ++k) {
      const double mid = std::sqrt(stable * unstable);
      const bool ok =
          below ? mat::check_stability(*law, mid, 1.0).stable : mat::check_stability(*law, 1.0, mid).stable;
      (ok ? stable : unstable) = mid;
    }
    return stable;
  };
  out.stable_lambda_min = mat::check_stability(*law, 0.15, 1.0).stable ? 0.15 : bisect(0.15, true);
  out.stable_lambda_max =
      mat::check_stability(*law, 1.0, 1 / 0.15).stable ? 1 / 0.15 : bisect(1 / 0.15, false);
}

}  // namespace

InverseFitResult fit_material(const std::vector<PinCompressionData>& pins,
                              const std::vector<ClosedFormData>& closed, const InverseFitOptions& o) {
  check_data(pins, closed);
  o.reference.validate();
  const MaterialFit fit(pins, closed, o);
  const auto ref_fit = fit.best_scale(fit.ref);
  if (!ref_fit)
    throw FeError("material fit: the FE cannot solve the datasets' compression with the reference law");
  const double s0 = ref_fit->first;
  fit.say(fmt::format("reference law scaled by {:.4g} to the data", s0));
  const mat::LeastSquaresProblem pr = fit.problem(fit.starting_law(s0), s0);
  mat::LeastSquaresOptions lo;
  lo.max_iterations = o.max_iterations;
  lo.confidence = o.confidence;
  lo.progress = [&](int it, double cost, int evals) {
    fit.say(fmt::format("iteration {}: sum of squared relative residuals {:.6g} ({} evaluations)", it, cost,
                        evals));
  };
  const mat::LeastSquaresResult ls = mat::levenberg_marquardt(pr, lo);

  InverseFitResult out;
  out.model = o.model;
  out.material = fit.to_law(ls.theta);
  out.names = pr.names;
  out.confidence = o.confidence;
  out.poisson_ratio = o.poisson_ratio;
  add_estimates(out, ls);
  fit.add_confidence_laws(out, ls);
  fit.add_datasets(out);
  add_stability(out);
  return out;
}

namespace {

// One law as the fit's JSON holds it; law_from_json reads it back.
nlohmann::json law_json(const mat::OgdenParameters& p) {
  return {{"mu_MPa", p.mu}, {"alpha", p.alpha}, {"D_per_MPa", p.D}};
}

mat::OgdenParameters law_from_json(const nlohmann::json& j) {
  mat::OgdenParameters p;
  p.mu = j.at("mu_MPa").get<std::vector<double>>();
  p.alpha = j.at("alpha").get<std::vector<double>>();
  p.D = j.at("D_per_MPa").get<std::vector<double>>();
  p.validate();
  return p;
}

}  // namespace

FittedLaws fitted_laws_from_json(const nlohmann::json& fit) {
  FittedLaws out;
  out.law = law_from_json(fit.at("ogden"));
  for (const auto& c : fit.at("confidence_laws"))
    out.confidence_laws.emplace_back(c.at("label").get<std::string>(), law_from_json(c));
  return out;
}

nlohmann::json to_json(const InverseFitResult& r) {
  nlohmann::json j;
  j["model"] = to_string(r.model);
  j["confidence"] = r.confidence;
  for (std::size_t k = 0; k < r.names.size(); ++k) {
    auto finite_or_null = [](double v) {
      return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
    };
    j["parameters"][r.names[k]] = {
        {"value", r.values[k]},
        {"standard_error", finite_or_null(r.standard_errors[k])},
        {"interval", {finite_or_null(r.interval_low[k]), finite_or_null(r.interval_high[k])}}};
  }
  j["parameter_order"] = r.names;
  auto cov = nlohmann::json::array();
  for (const auto& row : r.covariance) {
    auto jr = nlohmann::json::array();
    for (double v : row) jr.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
    cov.push_back(jr);
  }
  j["covariance"] = cov;
  j["ogden"] = law_json(r.material);
  j["residual_variance"] = r.residual_variance;
  j["poisson_ratio"] = r.poisson_ratio;
  auto laws = nlohmann::json::array();
  for (const auto& [label, law] : r.confidence_laws) {
    auto l = law_json(law);
    l["label"] = label;
    laws.push_back(l);
  }
  j["confidence_laws"] = laws;
  j["t_quantile"] = r.t_quantile;
  auto ds = nlohmann::json::array();
  for (const auto& d : r.datasets)
    ds.push_back({{"name", d.name},
                  {"x", d.x},
                  {"measured", d.measured},
                  {"fitted", d.fitted},
                  {"rms_relative", d.rms_relative},
                  {"max_abs_relative", d.max_abs_relative}});
  j["datasets"] = ds;
  j["iterations"] = r.iterations;
  j["evaluations"] = r.evaluations;
  j["converged"] = r.converged;
  j["stop_reason"] = r.stop_reason;
  j["stability"] = to_json(r.stability);
  j["stability"]["stable_lambda_min"] = r.stable_lambda_min;
  j["stability"]["stable_lambda_max"] = r.stable_lambda_max;
  return j;
}

nlohmann::json to_json(const tocd::sim::material::StabilityReport& s) {
  return {{"stable", s.stable},
          {"lambda_min", s.lambda_min},
          {"lambda_max", s.lambda_max},
          {"first_failure", s.first_failure}};
}

}  // namespace tocd::sim::fe

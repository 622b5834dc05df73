// Simulated samples: an analytic stand-in and tabulated (FE/MC-backed) curves.
#include "tocd/mocks/tissue.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "tocd/core/error.hpp"

namespace tocd::mocks {
namespace {

class AnalyticTissue final : public TissueModel {
 public:
  explicit AnalyticTissue(const AnalyticTissueParams& p) : p_(p) {
    const double x = p.pin_radius_mm / p.thickness_mm;
    const double kappa = 1.0 + 1.33 * x + 1.33 * x * x * x;
    // N per unit log strain: 2 a E* kappa h, with E* = E / (1 - nu^2) (MPa x mm^2 = N).
    stiffness_N_ = 2.0 * p.pin_radius_mm * p.youngs_modulus_MPa / (1.0 - p.poisson_ratio * p.poisson_ratio) *
                   kappa * p.thickness_mm;
  }

  double load_N(double d) const override { return stiffness_N_ * log_strain(d); }

  double transmission(double d) const override {
    const double eps = log_strain(d);
    const double remaining = p_.thickness_mm - std::clamp(d, 0.0, max_d());
    const double mu = p_.mu_eff_per_mm * (1.0 - p_.clearing * std::min(eps, 1.0));
    return std::exp(-mu * remaining);
  }

 private:
  // The log strain diverges at full compression; hold the curve at 95 % of the thickness.
  double max_d() const { return 0.95 * p_.thickness_mm; }
  double log_strain(double d) const { return -std::log(1.0 - std::clamp(d, 0.0, max_d()) / p_.thickness_mm); }

  AnalyticTissueParams p_;
  double stiffness_N_;
};

class TabulatedTissue final : public TissueModel {
 public:
  TabulatedTissue(std::vector<double> d, std::vector<double> f, std::vector<double> t)
      : d_(std::move(d)), f_(std::move(f)), t_(std::move(t)) {}
  double load_N(double d) const override { return interpolate(f_, d); }
  double transmission(double d) const override { return interpolate(t_, d); }

 private:
  double interpolate(const std::vector<double>& y, double x) const {
    if (x <= d_.front()) return y.front();
    if (x >= d_.back()) return y.back();
    const auto i = static_cast<std::size_t>(std::upper_bound(d_.begin(), d_.end(), x) - d_.begin());
    const double w = (x - d_[i - 1]) / (d_[i] - d_[i - 1]);
    return y[i - 1] + w * (y[i] - y[i - 1]);
  }
  std::vector<double> d_, f_, t_;
};

}  // namespace

std::shared_ptr<TissueModel> make_analytic_tissue(double thickness_mm) {
  AnalyticTissueParams p;
  p.thickness_mm = thickness_mm;
  return make_analytic_tissue(p);
}

std::shared_ptr<TissueModel> make_analytic_tissue(const AnalyticTissueParams& p) {
  const bool ok = p.thickness_mm > 0 && p.pin_radius_mm > 0 && p.youngs_modulus_MPa > 0 &&
                  p.poisson_ratio >= 0 && p.poisson_ratio < 0.5 && p.mu_eff_per_mm >= 0 && p.clearing >= 0 &&
                  p.clearing < 1 &&
                  std::isfinite(p.thickness_mm + p.pin_radius_mm + p.youngs_modulus_MPa + p.mu_eff_per_mm);
  if (!ok)
    throw ConfigError(fmt::format(
        "analytic tissue needs thickness, pin radius, modulus > 0, Poisson ratio in "
        "[0, 0.5), mu_eff >= 0, clearing in [0, 1) (got {} mm, {} mm, {} MPa, {}, {} "
        "/mm, {})",
        p.thickness_mm, p.pin_radius_mm, p.youngs_modulus_MPa, p.poisson_ratio, p.mu_eff_per_mm, p.clearing));
  return std::make_shared<AnalyticTissue>(p);
}

std::shared_ptr<TissueModel> make_tabulated_tissue(std::vector<double> d_mm, std::vector<double> load_N,
                                                   std::vector<double> transmission) {
  if (d_mm.size() < 2 || load_N.size() != d_mm.size() || transmission.size() != d_mm.size())
    throw ConfigError(
        fmt::format("tabulated tissue needs >= 2 points and equally long tables (got {} "
                    "displacements, {} loads, {} transmissions)",
                    d_mm.size(), load_N.size(), transmission.size()));
  for (std::size_t i = 0; i < d_mm.size(); ++i) {
    if (!std::isfinite(d_mm[i]) || !std::isfinite(load_N[i]) || !std::isfinite(transmission[i]) ||
        transmission[i] < 0.0 || transmission[i] > 2.0)
      throw ConfigError(
          fmt::format("tabulated tissue point {}: values must be finite, transmission in [0, 2] "
                      "(got d = {}, load = {}, T = {})",
                      i, d_mm[i], load_N[i], transmission[i]));
    if (i > 0 && !(d_mm[i] > d_mm[i - 1]))
      throw ConfigError(
          fmt::format("tabulated tissue point {}: displacements must increase (got {} after {})", i, d_mm[i],
                      d_mm[i - 1]));
  }
  return std::make_shared<TabulatedTissue>(std::move(d_mm), std::move(load_N), std::move(transmission));
}

}  // namespace tocd::mocks

// Quasi-linear viscoelastic response along a sampled history (qlv.hpp).
#include "tocd/sim/material/qlv.hpp"

#include <cmath>

#include <fmt/format.h>

#include "tocd/sim/material/ogden.hpp"

namespace tocd::sim::material {

double PronySeries::relaxation(double t_s) const {
  double k = 1.0;
  for (const auto& term : terms) k += term.g * std::exp(-t_s / term.tau_s);
  return k;
}

double PronySeries::instantaneous() const {
  double k = 1.0;
  for (const auto& term : terms) k += term.g;
  return k;
}

void PronySeries::validate() const {
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (!std::isfinite(terms[i].g) || terms[i].g < 0)
      throw MaterialError(fmt::format("Prony term {}: g = {} must be finite and >= 0", i + 1, terms[i].g));
    if (!std::isfinite(terms[i].tau_s) || !(terms[i].tau_s > 0))
      throw MaterialError(
          fmt::format("Prony term {}: tau = {} s must be finite and > 0", i + 1, terms[i].tau_s));
  }
}

namespace {

// phi(x) = (1 - exp(-x)) / x and its derivative, accurate at small x where both forms cancel.
double phi(double x) {
  return x < 1e-8 ? 1.0 - 0.5 * x : -std::expm1(-x) / x;
}
double phi_prime(double x) {
  if (x < 1e-4) return -0.5 + x / 3.0 - x * x / 8.0;
  return (std::exp(-x) * (1.0 + x) - 1.0) / (x * x);
}

}  // namespace

std::vector<double> prony_history(const std::vector<double>& t_s, const std::vector<double>& elastic,
                                  double tau_s, std::vector<double>* dh_dtau) {
  if (t_s.size() != elastic.size())
    throw MaterialError(
        fmt::format("QLV history: {} times but {} elastic loads", t_s.size(), elastic.size()));
  if (!std::isfinite(tau_s) || !(tau_s > 0))
    throw MaterialError(fmt::format("QLV history: tau = {} s must be > 0", tau_s));
  std::vector<double> h(t_s.size(), 0.0);
  if (dh_dtau) dh_dtau->assign(t_s.size(), 0.0);
  double dh = 0.0;
  for (std::size_t n = 1; n < t_s.size(); ++n) {
    const double d = t_s[n] - t_s[n - 1];
    if (!(d >= 0)) throw MaterialError(fmt::format("QLV history: time goes back at sample {}", n));
    const double x = d / tau_s;
    const double decay = std::exp(-x);
    const double step = elastic[n] - elastic[n - 1];
    h[n] = decay * h[n - 1] + step * phi(x);
    if (dh_dtau) {
      // d/dtau of exp(-d/tau) is exp(-d/tau) d/tau^2 = decay x / tau; of phi(x), phi'(x) (-x / tau).
      dh = decay * dh + decay * (x / tau_s) * h[n - 1] + step * phi_prime(x) * (-x / tau_s);
      (*dh_dtau)[n] = dh;
    }
  }
  return h;
}

std::vector<double> qlv_response(const std::vector<double>& t_s, const std::vector<double>& elastic,
                                 const PronySeries& prony) {
  if (t_s.size() != elastic.size())
    throw MaterialError(fmt::format("QLV response: {} times but {} loads", t_s.size(), elastic.size()));
  prony.validate();
  std::vector<double> f = elastic;
  for (const auto& term : prony.terms) {
    const auto h = prony_history(t_s, elastic, term.tau_s);
    for (std::size_t n = 0; n < f.size(); ++n) f[n] += term.g * h[n];
  }
  return f;
}

}  // namespace tocd::sim::material

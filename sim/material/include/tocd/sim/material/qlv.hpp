#pragma once

// Quasi-linear viscoelasticity (Fung, "Biomechanics: Mechanical Properties of Living Tissues",
// 1993, ch. 7): the load is a hereditary integral of the elastic response over the history,
//   F(t) = integral from -inf to t of K(t - u) dF_e(u),   K(t) = 1 + sum_i g_i exp(-t / tau_i),
// with F_e the equilibrium (fully relaxed) elastic response at the current deformation and K
// the reduced relaxation function normalised to 1 at equilibrium. Fung's normalisation,
// G(t) = K(t) / K(0) with G(0) = 1, describes the same material with the instantaneous elastic
// response K(0) F_e; its Prony coefficients are g_i / K(0). The equilibrium normalisation is
// used here because a pin-compression run holds long enough to see the relaxed load, which
// the FE computes, and because it is what a standard linear solid's overstress fraction is.

#include <vector>

namespace tocd::sim::material {

struct PronyTerm {
  double g = 0;      ///< overstress carried per unit of equilibrium load increment (>= 0)
  double tau_s = 1;  ///< its relaxation time (> 0)
};

struct PronySeries {
  std::vector<PronyTerm> terms;
  /// K(t) = 1 + sum g_i exp(-t / tau_i) for t >= 0.
  double relaxation(double t_s) const;
  /// K(0) = 1 + sum g_i: the instantaneous over the equilibrium response.
  double instantaneous() const;
  /// Throws MaterialError naming the term with a negative or non-finite g or a tau <= 0.
  void validate() const;
};

/// The overstress history of one Prony term for unit g: h(t_n) = integral of
/// exp(-(t_n - u) / tau) dF_e(u) along a sampled history (t_n ascending, F_e at each t_n, the
/// history starting at rest at t_0), F_e taken linear in time between samples, for which the
/// recursion
///   h_{n+1} = exp(-D / tau) h_n + (F_{n+1} - F_n) (tau / D) (1 - exp(-D / tau)),  D = t_{n+1} - t_n,
/// is exact (D = 0: an instantaneous step, h += dF). `dh_dtau` (when not null) receives the
/// derivative of h with respect to tau at every sample, by the same recursion differentiated.
/// Throws MaterialError on sizes that differ, a time that goes back, or tau <= 0.
std::vector<double> prony_history(const std::vector<double>& t_s, const std::vector<double>& elastic,
                                  double tau_s, std::vector<double>* dh_dtau = nullptr);

/// F(t_n) = F_e(t_n) + sum_i g_i h_i(t_n) (prony_history per term).
std::vector<double> qlv_response(const std::vector<double>& t_s, const std::vector<double>& elastic,
                                 const PronySeries& prony);

}  // namespace tocd::sim::material

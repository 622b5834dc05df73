#pragma once

// A pin-compression run written down in closed form: ramps at constant speed between held
// displacements, the elastic load piecewise linear in the displacement (so linear in time on
// every ramp), and the QLV overstress and the drained displacement of every ramp superposed
// by their closed forms (integral of exp(-(t-u)/tau) over a ramp of constant rate):
//   h_ramp(t) = (dF / T_r) tau (1 - exp(-u / tau)) exp(-(t - t_r - u) / tau),  u = clamp(t - t_r, 0, T_r).
// Nothing here calls the library's recursion, so the identification is checked against an
// independent forward model.

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "tocd/analysis/identified.hpp"
#include "tocd/analysis/run_history.hpp"

namespace tocd::analysis::testing {

struct SyntheticTruth {
  double offset_N = 0.0, scale = 1.25, g = 0.3, tau_s = 20.0;
  double delayed = 0.3, delayed_tau_s = 20.0;
  double load_noise_N = 0.002, transmission_noise = 0.0005;
  double transmission_relative_noise = 0.0;  ///< a share of T, added to transmission_noise (the meter's)
};

struct SyntheticRun {
  RunHistory history;
  std::vector<double> knots_mm{0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5};
  std::vector<double> elastic_N{0.0, 0.003, 0.009, 0.02, 0.041, 0.096, 0.285};  // published law's shape
  std::vector<double> T_eq{0.124, 0.196, 0.299, 0.448, 0.575, 0.692, 0.790};
};

inline double ramp_history(double t, double t_start, double duration, double change, double tau) {
  if (t <= t_start) return 0.0;
  const double u = std::min(t - t_start, duration);
  return change / duration * tau * (1 - std::exp(-u / tau)) * std::exp(-(t - t_start - u) / tau);
}

inline double piecewise(const std::vector<double>& x, const std::vector<double>& y, double at) {
  return interpolate(x, y, at);
}

/// Holds of `hold_s` at each knot (the first at contact), ramps at `speed` between them; the
/// tester read at `tester_hz`, the meter at 10 Hz; the last 5 s of each hold is its recording
/// window.
inline SyntheticRun make_synthetic_run(const SyntheticTruth& truth, std::uint64_t seed, double hold_s = 12.0,
                                       double speed_mm_per_s = 0.5, double tester_hz = 200.0) {
  SyntheticRun s;
  RunHistory& h = s.history;
  h.run_id = 1;
  h.thickness_mm = 2.5;
  struct Ramp {
    double t0, duration, d0, d1;
  };
  std::vector<Ramp> ramps;
  std::vector<std::pair<double, double>> holds;  // [start, end]
  double t = 0;
  holds.push_back({0.0, hold_s});
  t = hold_s;
  for (std::size_t k = 1; k < s.knots_mm.size(); ++k) {
    const double duration = (s.knots_mm[k] - s.knots_mm[k - 1]) / speed_mm_per_s;
    ramps.push_back({t, duration, s.knots_mm[k - 1], s.knots_mm[k]});
    t += duration;
    holds.push_back({t, t + hold_s});
    t += hold_s;
  }
  auto displacement = [&](double time) {
    for (const auto& r : ramps)
      if (time >= r.t0 && time <= r.t0 + r.duration) return r.d0 + (r.d1 - r.d0) * (time - r.t0) / r.duration;
    double d = 0;
    for (const auto& r : ramps)
      if (time > r.t0 + r.duration) d = r.d1;
    return d;
  };
  auto overstress = [&](double time, double tau) {  // of the elastic load, unit g
    double sum = 0;
    for (const auto& r : ramps) {
      const double change =
          piecewise(s.knots_mm, s.elastic_N, r.d1) - piecewise(s.knots_mm, s.elastic_N, r.d0);
      sum += ramp_history(time, r.t0, r.duration, change, tau);
    }
    return sum;
  };
  auto lag = [&](double time, double tau) {  // d - drained d
    double sum = 0;
    for (const auto& r : ramps) sum += ramp_history(time, r.t0, r.duration, r.d1 - r.d0, tau);
    return sum;
  };
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  const double dt = 1.0 / tester_hz;
  const auto n = static_cast<std::size_t>(std::floor(t / dt));
  for (std::size_t k = 0; k <= n; ++k) {
    const double time = static_cast<double>(k) * dt;
    const double d = displacement(time);
    h.tester_t_s.push_back(time);
    h.displacement_mm.push_back(d);
    h.load_N.push_back(truth.offset_N +
                       truth.scale *
                           (piecewise(s.knots_mm, s.elastic_N, d) + truth.g * overstress(time, truth.tau_s)) +
                       truth.load_noise_N * normal(rng));
  }
  for (double time = 0.05; time < t; time += 0.1) {
    const double d = displacement(time), dd = d - lag(time, truth.delayed_tau_s);
    h.power_t_s.push_back(time);
    const double light = (1 - truth.delayed) * piecewise(s.knots_mm, s.T_eq, d) +
                         truth.delayed * piecewise(s.knots_mm, s.T_eq, dd);
    h.transmission.push_back(light +
                             std::hypot(truth.transmission_noise, truth.transmission_relative_noise * light) *
                                 normal(rng));
  }
  for (std::size_t k = 0; k < holds.size(); ++k) {
    Hold hold;
    hold.step_index = static_cast<int>(k);
    hold.displacement_mm = s.knots_mm[k];
    auto index = [&](double time) { return static_cast<std::size_t>(std::ceil(time / dt - 1e-9)); };
    hold.first = index(holds[k].first) + 1;  // after the ramp's last reading
    hold.last = std::min(index(holds[k].second) - 1, n);
    hold.record_first = index(holds[k].second - 5.0);
    h.holds.push_back(hold);
  }
  return s;
}

/// Whether a parameter's 95 % interval holds its truth.
inline bool covers(const IdentifiedParameter& p, double truth) {
  return p.lo <= truth && truth <= p.hi;
}

/// A run with the demo's holds (8 s), its tester at 50 Hz and its meter's noise (0.2 % of the
/// light over a floor of 2e-10 W of 1 mW), the delayed share and its time drawn from the
/// simulated samples' ranges (0 to 0.5, 8 to 40 s), the noise from `noise_seed`.
struct DrawnClearingRun {
  SyntheticTruth truth;
  SyntheticRun run;
};

inline DrawnClearingRun demo_holds_clearing_run(std::mt19937_64& draw, std::uint64_t noise_seed) {
  std::uniform_real_distribution<double> u01;
  DrawnClearingRun d;
  d.truth.delayed = 0.5 * u01(draw);
  d.truth.delayed_tau_s = 8.0 + 32.0 * u01(draw);
  d.truth.transmission_noise = 2e-7;
  d.truth.transmission_relative_noise = 0.002;
  d.run = make_synthetic_run(d.truth, noise_seed, 8.0, 0.5, 50.0);
  return d;
}

}  // namespace tocd::analysis::testing

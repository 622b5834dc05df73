// A recorded pin displacement history through the biphasic FE, T at chosen times
// (docs/water.md, "Time course of a recorded run").
#include "tocd/sim/study/water_history.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "elapsed.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/poro/solver.hpp"
#include "water_transmission.hpp"

namespace tocd::sim::study {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void mark_not_computed(WaterHistoryPoint& p, const std::string& why) {
  p.computed = false;
  p.failure = why;
  p.T = p.T_stderr = p.pin_force_N = p.water_outflow_mm3 = kNaN;
}

}  // namespace

double DisplacementHistory::at(double t) const {
  if (t_s.empty()) return 0;
  if (t <= t_s.front()) return d_mm.front();
  if (t >= t_s.back()) return d_mm.back();
  const auto hi = static_cast<std::size_t>(std::upper_bound(t_s.begin(), t_s.end(), t) - t_s.begin());
  const std::size_t lo = hi - 1;
  const double u = (t - t_s[lo]) / (t_s[hi] - t_s[lo]);
  return d_mm[lo] + u * (d_mm[hi] - d_mm[lo]);
}

void DisplacementHistory::validate(double thickness_mm) const {
  if (t_s.size() != d_mm.size() || t_s.size() < 2)
    throw tocd::ConfigError(
        fmt::format("displacement history: needs at least two knots and as many times as depths (got {} "
                    "times, {} depths)",
                    t_s.size(), d_mm.size()));
  if (t_s.front() != 0)
    throw tocd::ConfigError(fmt::format("displacement history: must start at t = 0 (got {} s)", t_s.front()));
  // The biphasic state at t = 0 is the undeformed skin, so the pin must start on the surface.
  if (d_mm.front() != 0)
    throw tocd::ConfigError(fmt::format(
        "displacement history: must start with the pin on the surface, d = 0 (got {} mm)", d_mm.front()));
  for (std::size_t i = 0; i < t_s.size(); ++i) {
    if (!std::isfinite(t_s[i]) || (i > 0 && !(t_s[i] > t_s[i - 1])))
      throw tocd::ConfigError(
          fmt::format("displacement history: times must be finite and ascending (knot {})", i));
    if (!(d_mm[i] >= 0) || !(d_mm[i] < thickness_mm))
      throw tocd::ConfigError(
          fmt::format("displacement history: depth {} mm at t = {} s is not in [0, thickness {} mm)", d_mm[i],
                      t_s[i], thickness_mm));
  }
}

void validate(const WaterHistoryRequest& r) {
  if (!(r.thickness_mm > 0))
    throw tocd::ConfigError(fmt::format("water history: thickness must be > 0 (got {} mm)", r.thickness_mm));
  r.history.validate(r.thickness_mm);
  if (r.times_s.empty()) throw tocd::ConfigError("water history: no time points");
  for (std::size_t i = 0; i < r.times_s.size(); ++i)
    if (!(r.times_s[i] >= 0) || !(r.times_s[i] <= r.history.t_s.back()) ||
        (i > 0 && !(r.times_s[i] > r.times_s[i - 1])))
      throw tocd::ConfigError(fmt::format(
          "water history: time points must be ascending and within the history [0, {} s] (point {}: {} s)",
          r.history.t_s.back(), i, r.times_s[i]));
  if (!(r.drained_poisson > -1 && r.drained_poisson < 0.5))
    throw tocd::ConfigError(fmt::format(
        "water history: drained Poisson's ratio must lie in (-1, 0.5) (got {})", r.drained_poisson));
  if (r.photons == 0) throw tocd::ConfigError("water history: photons must be positive");
  if (!(r.max_step_s > 0) || !(r.max_increment_mm > 0))
    throw tocd::ConfigError("water history: max_step_s and max_increment_mm must be positive");
  native_water_fraction(r.optics);
}

std::vector<WaterHistoryPoint> predict_water_history(const WaterHistoryRequest& r) {
  validate(r);
  const detail::WaterPinGeometry g{r.thickness_mm, r.outer_radius_mm, r.pin_radius_mm, r.fe_columns,
                                   r.fe_rows};
  const DisplacementHistory h = r.history;
  poro::PoroSolver solver(detail::water_pin_model(g, r.skeleton, r.drained_poisson, r.permeability,
                                                  [h](double t) { return h.at(t); }));

  // Every FE step ends on a knot or a time point: the loads are piecewise linear between them.
  std::vector<double> ends = r.history.t_s;
  ends.insert(ends.end(), r.times_s.begin(), r.times_s.end());
  std::sort(ends.begin(), ends.end());
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());

  const auto fe_start = Clock::now();
  double t = 0;
  std::string failure;  // once set, the FE state is no longer that of the history
  std::size_t next_end = 0;
  int halvings = 0;  // step_halvings counts one advance_to: summed here between time points
  const auto advance_to = [&](double to) {
    for (; next_end < ends.size() && ends[next_end] <= to; ++next_end) {
      const double b = ends[next_end];
      if (b <= t) continue;
      const double span = b - t, travel = std::abs(h.at(b) - h.at(t));
      const int n = std::max({1, static_cast<int>(std::ceil(span / r.max_step_s - 1e-9)),
                              static_cast<int>(std::ceil(travel / r.max_increment_mm - 1e-9))});
      const double from = t;
      for (int k = 1; k <= n; ++k) {
        const double tk = k == n ? b : from + span * k / n;
        if (r.fe_budget_s > 0 && seconds_since(fe_start) > r.fe_budget_s) {
          failure = fmt::format("biphasic FE: time budget of {} s spent at t = {:.3f} s (d = {:.4f} mm)",
                                r.fe_budget_s, t, h.at(t));
          return;
        }
        try {
          halvings += solver.advance_to(tk).step_halvings;
        } catch (const tocd::Error& e) {
          failure =
              fmt::format("biphasic FE failed between t = {:.3f} and {:.3f} s (d = {:.4f} -> {:.4f} mm): {}",
                          t, tk, h.at(t), h.at(tk), e.what());
          return;
        }
        t = tk;
      }
    }
  };

  std::vector<WaterHistoryPoint> out;
  for (double when : r.times_s) {
    WaterHistoryPoint p;
    p.time_s = when;
    p.displacement_mm = h.at(when);
    const auto t0 = Clock::now();
    halvings = 0;
    if (failure.empty()) advance_to(when);
    p.fe_seconds = seconds_since(t0);
    p.fe_step_halvings = halvings;
    if (!failure.empty()) {
      mark_not_computed(p, failure);
    } else {
      try {
        detail::record_transmission(p, solver, g, p.displacement_mm, r);
        p.computed = true;
      } catch (const tocd::Error& e) {
        // A mesh of this state alone failed; the FE goes on, so later points may still come.
        mark_not_computed(p,
                          fmt::format("composite mesh or Monte Carlo at t = {:.3f} s: {}", when, e.what()));
      }
    }
    out.push_back(p);
    if (r.progress) r.progress(out.size(), r.times_s.size());
  }
  return out;
}

nlohmann::json to_json(const WaterHistoryPoint& p) {
  nlohmann::json j = {{"time_s", p.time_s}, {"displacement_mm", p.displacement_mm}, {"computed", p.computed}};
  if (!p.computed) {
    j["failure"] = p.failure;
    return j;
  }
  add_to_json(j, p);
  j["fe_step_halvings"] = p.fe_step_halvings;
  return j;
}

}  // namespace tocd::sim::study

#include "tocd/sim/study/water_time_course.hpp"

#include <cmath>

#include <fmt/format.h>

#include "elapsed.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/poro/solver.hpp"
#include "water_transmission.hpp"

namespace tocd::sim::study {

namespace {

detail::WaterPinGeometry geometry_of(const WaterTimeCourseRequest& r) {
  return {r.thickness_mm, r.outer_radius_mm, r.pin_radius_mm, r.fe_columns, r.fe_rows};
}

}  // namespace

void validate(const WaterTimeCourseRequest& r) {
  if (!(r.thickness_mm > 0) || !(r.displacement_mm > 0) || !(r.displacement_mm < r.thickness_mm))
    throw tocd::ConfigError(
        fmt::format("water time course: displacement must lie in (0, thickness) (got {} mm of {} mm)",
                    r.displacement_mm, r.thickness_mm));
  if (!(r.ramp_s > 0))
    throw tocd::ConfigError(fmt::format("water time course: ramp_s must be > 0 (got {})", r.ramp_s));
  if (r.times_s.empty()) throw tocd::ConfigError("water time course: no time points");
  for (std::size_t i = 0; i < r.times_s.size(); ++i)
    if (!(r.times_s[i] >= 0) || (i > 0 && !(r.times_s[i] > r.times_s[i - 1])))
      throw tocd::ConfigError("water time course: time points must be >= 0 and ascending");
  if (!(r.drained_poisson > -1 && r.drained_poisson < 0.5))
    throw tocd::ConfigError(fmt::format(
        "water time course: drained Poisson's ratio must lie in (-1, 0.5) (got {})", r.drained_poisson));
  if (r.photons == 0 || r.steps_per_interval < 1)
    throw tocd::ConfigError("water time course: photons and steps_per_interval must be positive");
  native_water_fraction(r.optics);
}

std::vector<WaterTimePoint> predict_water_time_course(const WaterTimeCourseRequest& r) {
  validate(r);
  const double d = r.displacement_mm, ramp = r.ramp_s;
  const auto g = geometry_of(r);
  poro::PoroSolver solver(
      detail::water_pin_model(g, r.skeleton, r.drained_poisson, r.permeability,
                              [d, ramp](double t) { return d * std::min(t / ramp, 1.0); }));
  std::vector<WaterTimePoint> out;
  // Ramp in steps_per_interval x 10 steps (large strain, contact spreading), then each
  // interval of the hold in
  // steps_per_interval steps.
  double t = 0;
  const auto advance = [&](double to, int steps) {
    const double from = t;
    for (int k = 1; k <= steps; ++k) solver.advance_to(from + (to - from) * k / steps);
    t = to;
  };
  for (double hold : r.times_s) {
    WaterTimePoint p;
    p.time_s = hold;
    auto t0 = Clock::now();
    if (t < r.ramp_s) advance(r.ramp_s, 10 * r.steps_per_interval);
    if (r.ramp_s + hold > t) advance(r.ramp_s + hold, r.steps_per_interval);
    p.fe_seconds = seconds_since(t0);
    detail::record_transmission(p, solver, g, r.displacement_mm, r);
    out.push_back(p);
    if (r.progress) r.progress(out.size(), r.times_s.size());
  }
  return out;
}

nlohmann::json to_json(const WaterTimePoint& p) {
  nlohmann::json j = {{"time_s", p.time_s}};
  add_to_json(j, p);
  return j;
}

}  // namespace tocd::sim::study

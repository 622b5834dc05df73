// A recorded run's holds through the biphasic FE with water-content optics, next to the power
// measured at the same times (docs/water.md, "Time course of a recorded run").
#include "tocd/analysis/run_water_course.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "tocd/core/error.hpp"
#include "tocd/core/running_stats.hpp"
#include "tocd/sim/geometry/douglas_peucker.hpp"
#include "tocd/sim/study/predictor.hpp"
#include "tocd/sim/study/run_settings.hpp"

namespace tocd::analysis {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
namespace st = tocd::sim::study;

double seconds_between(std::int64_t from_ns, std::int64_t to_ns) {
  return static_cast<double>(to_ns - from_ns) * 1e-9;
}

// Douglas-Peucker on (t, d) with the error measured in d at each sample's own time: keeps the
// fewest knots (among the samples) whose linear interpolation is within tol of every sample.
std::vector<std::size_t> knots_within(const std::vector<double>& t, const std::vector<double>& d,
                                      double tol) {
  return sim::geometry::douglas_peucker(t.size(), tol, [&](std::size_t i, std::size_t a, std::size_t b) {
    const double u = (t[i] - t[a]) / (t[b] - t[a]);
    return std::abs(d[i] - (d[a] + u * (d[b] - d[a])));
  });
}

// T of the glass-only configuration (pin tip on the slide, no skin), the reference the
// engine's stored predictions divide by ("T(step) / T(glass-only baseline)").
st::Prediction glass_baseline(const RunWaterCourseOptions& o) {
  st::PredictionRequest r;
  r.baseline = true;
  st::copy_run_settings(r, o);
  r.pin_radius_mm = o.pin_radius_mm;
  st::Predictor predictor(1);
  return predictor.predict(r);
}

}  // namespace

RunDisplacementHistory displacement_history_from_run(const db::Reader& reader, std::int64_t run_id,
                                                     std::int64_t until_ns, double tolerance_mm) {
  if (!(tolerance_mm > 0))
    throw tocd::ConfigError(
        fmt::format("displacement history tolerance must be > 0 (got {} mm)", tolerance_mm));
  // Across a resume the pin was retracted and re-approached with no samples in the gap (and
  // after a reboot the monotonic clock restarts): no history to hand the FE.
  if (const auto segments = reader.anchors(run_id).size(); segments > 1)
    throw tocd::Error(fmt::format(
        "run {} was resumed ({} recording segments): the pin history across a resume is not modelled", run_id,
        segments));
  const auto ch = reader.channel(run_id, "displacement");
  if (!ch)
    throw tocd::Error(
        fmt::format("run {}: no displacement channel (no tester), so no pin history to follow", run_id));
  db::SampleQuery q;
  q.to_t_ns = until_ns;
  std::vector<double> t, d;
  std::int64_t t0 = 0;
  for (const auto& s : reader.samples(ch->id, q)) {
    if (!std::isfinite(s.value)) continue;
    if (t.empty()) t0 = s.t_ns;
    const double ts = seconds_between(t0, s.t_ns);
    if (!t.empty() && !(ts > t.back())) continue;  // a repeated timestamp adds nothing
    t.push_back(ts);
    d.push_back(std::max(0.0, s.value));
  }
  if (t.size() < 2)
    throw tocd::Error(fmt::format("run {}: fewer than two displacement samples up to the last hold", run_id));
  if (d.front() > tolerance_mm)
    throw tocd::Error(fmt::format(
        "run {}: the displacement record starts with the pin {} mm deep; the biphasic model starts from "
        "undeformed skin",
        run_id, d.front()));
  d.front() = 0;
  RunDisplacementHistory out;
  out.t0_ns = t0;
  out.samples = t.size();
  out.tolerance_mm = tolerance_mm;
  for (std::size_t i : knots_within(t, d, tolerance_mm)) {
    out.history.t_s.push_back(t[i]);
    out.history.d_mm.push_back(d[i]);
  }
  return out;
}

MeasuredT measured_T_between(const db::Reader& reader, std::int64_t power_channel, double baseline_power_W,
                             std::int64_t from_ns, std::int64_t to_ns) {
  db::SampleQuery q;
  q.from_t_ns = from_ns;
  q.to_t_ns = to_ns;
  RunningStats s;
  for (const auto& x : reader.samples(power_channel, q))
    if (std::isfinite(x.value)) s.add(x.value);
  if (s.n() == 0) return {kNaN, kNaN, 0};
  const double se = s.n() > 1 ? s.std() / std::sqrt(static_cast<double>(s.n())) : kNaN;
  return {s.mean() / baseline_power_W, se / baseline_power_W, s.n()};
}

namespace {

// The biphasic request along the run's displacement history; its time points are added by
// add_points.
st::WaterHistoryRequest water_request(const RunWaterCourse& out, const RunWaterCourseOptions& o) {
  st::WaterHistoryRequest req;
  req.history = out.history.history;
  req.thickness_mm = out.thickness_mm;
  req.pin_radius_mm = o.pin_radius_mm;
  req.drained_poisson = o.drained_poisson;
  req.permeability.k0_mm4_per_Ns = o.k0_mm4_per_Ns;
  req.fe_budget_s = o.fe_budget_s;
  st::copy_run_settings(req, o);
  return req;
}

// Each step's time points (out.options.points_per_hold, spread over its recording window) with
// the measured T averaged around each; their times go to the request.
void add_points(const db::Reader& reader, const std::vector<db::StepRecord>& steps,
                std::int64_t power_channel, double baseline_power_W, RunWaterCourse& out,
                st::WaterHistoryRequest& req) {
  const RunWaterCourseOptions& o = out.options;
  const std::int64_t half = static_cast<std::int64_t>(0.5 * o.window_s * 1e9);
  const double t_end = req.history.t_s.back();
  for (const auto& s : steps) {
    WaterCourseStep ws;
    ws.index = s.index;
    ws.target_displacement_mm = s.target_displacement_mm;
    ws.window_from_s = seconds_between(out.history.t0_ns, s.recorded_from_t_ns);
    ws.window_to_s = seconds_between(out.history.t0_ns, s.recorded_to_t_ns);
    const std::int64_t a = s.recorded_from_t_ns + half, b = s.recorded_to_t_ns - half;
    // Points closer than an averaging window would share their samples: one, in the middle.
    const int n = b - a >= 2 * half ? o.points_per_hold : 1;
    for (int k = 0; k < n; ++k) {
      const std::int64_t at = n == 1
                                  ? (s.recorded_from_t_ns + s.recorded_to_t_ns) / 2
                                  : a + static_cast<std::int64_t>(static_cast<double>(b - a) * k / (n - 1));
      const double ts = seconds_between(out.history.t0_ns, at);
      // A window before the first displacement sample has no pin history to model.
      if (ts < 0 || ts > t_end) continue;
      if (!req.times_s.empty() && !(ts > req.times_s.back())) continue;  // overlapping windows
      WaterCoursePoint p;
      p.t_s = ts;
      p.t_window_s = seconds_between(s.recorded_from_t_ns, at);
      p.measured = measured_T_between(reader, power_channel, baseline_power_W,
                                      std::max(s.recorded_from_t_ns, at - half),
                                      std::min(s.recorded_to_t_ns, at + half));
      req.times_s.push_back(ts);
      ws.points.push_back(p);
    }
    out.steps.push_back(std::move(ws));
  }
}

// The predicted points, in the order their times were requested, relative to the glass-only
// baseline.
void fill_predictions(RunWaterCourse& out, const std::vector<st::WaterHistoryPoint>& predicted,
                      const st::Prediction& base) {
  std::size_t k = 0;
  for (auto& ws : out.steps)
    for (auto& p : ws.points) {
      const auto& q = p.predicted = predicted.at(k++);
      if (q.computed) {
        p.T = q.T / base.T;
        p.T_se = p.T * std::hypot(q.T_stderr / q.T, base.T_stderr / base.T);
      } else {
        p.T = p.T_se = kNaN;
      }
    }
}

}  // namespace

RunWaterCourse run_water_course(const db::Reader& reader, std::int64_t run_id,
                                const RunWaterCourseOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  if (o.points_per_hold < 1 || o.points_per_hold > 100)
    throw tocd::ConfigError(fmt::format("points per hold must be 1..100 (got {})", o.points_per_hold));
  if (!(o.window_s > 0))
    throw tocd::ConfigError(fmt::format("averaging window must be > 0 s (got {})", o.window_s));
  const auto say = [&](const std::string& s) {
    if (o.progress) o.progress(s);
  };
  const db::RunRecord run = reader.run(run_id);
  const auto power = reader.channel(run_id, "power");
  if (!power) throw tocd::Error(fmt::format("run {}: no power channel, so no measured transmission", run_id));
  if (!(run.baseline_power_W > 0))
    throw tocd::Error(fmt::format("run {}: no baseline power, so no measured transmission", run_id));
  const auto specimen = run.sample_id != 0 ? reader.sample(run.sample_id) : std::nullopt;
  if (!specimen || !(specimen->thickness_mm > 0))
    throw tocd::Error(fmt::format("run {}: no sample thickness, so no biphasic model of it", run_id));

  std::vector<db::StepRecord> steps;
  for (const auto& s : reader.steps(run_id))
    if (s.completed && s.recorded_to_t_ns > s.recorded_from_t_ns) steps.push_back(s);
  if (steps.empty())
    throw tocd::Error(fmt::format("run {}: no completed step with a recording window", run_id));

  RunWaterCourse out;
  out.run_id = run_id;
  out.thickness_mm = specimen->thickness_mm;
  out.options = o;
  out.history = displacement_history_from_run(reader, run_id, steps.back().recorded_to_t_ns, o.tolerance_mm);
  say(fmt::format("run {}: displacement history {} knots for {} samples (within {} mm), {:.1f} s", run_id,
                  out.history.history.t_s.size(), out.history.samples, o.tolerance_mm,
                  out.history.history.t_s.back()));

  st::WaterHistoryRequest req = water_request(out, o);
  add_points(reader, steps, power->id, run.baseline_power_W, out, req);
  if (req.times_s.empty())
    throw tocd::Error(fmt::format("run {}: no recording window lies within the displacement record", run_id));

  say(fmt::format("glass-only baseline: {} photons", o.photons));
  const auto base = glass_baseline(o);
  out.baseline_T = base.T;
  out.baseline_T_se = base.T_stderr;

  if (o.point_progress) req.progress = o.point_progress;
  say(fmt::format("biphasic FE along the run, {} time points (mesh + Monte Carlo each)", req.times_s.size()));
  const auto predicted = st::predict_water_history(req);
  fill_predictions(out, predicted, base);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

std::string format_run_water_course(const RunWaterCourse& c) {
  const auto& o = c.options;
  std::string s = fmt::format(
      "run {}: water-content optics along the recorded pin displacement ({} knots), {} mm sample, drained "
      "Poisson's ratio {}, k0 {} mm^4/(N s), {} photons per point; T relative to the glass-only baseline "
      "(T_glass {:.5f} +- {:.5f}); measured T averaged over {} s around each t\n",
      c.run_id, c.history.history.t_s.size(), c.thickness_mm, o.drained_poisson, o.k0_mm4_per_Ns, o.photons,
      c.baseline_T, c.baseline_T_se, o.window_s);
  s += fmt::format("{:>4} {:>7} {:>8} {:>8} {:>8} {:>9} {:>8} {:>9} {:>8} {:>10}\n", "step", "d_mm", "t_s",
                   "t_win_s", "d_now", "meas_T", "+-", "pred_T", "+-MC", "pin_F_N");
  std::string failure;
  for (const auto& st : c.steps)
    for (const auto& p : st.points) {
      const std::string meas = p.measured.n > 0
                                   ? fmt::format("{:>9.4f} {:>8.4f}", p.measured.T, p.measured.se)
                                   : fmt::format("{:>9} {:>8}", "-", "-");
      const auto& q = p.predicted;
      const std::string pred = q.computed
                                   ? fmt::format("{:>9.4f} {:>8.4f} {:>10.5f}", p.T, p.T_se, q.pin_force_N)
                                   : fmt::format("{:>9} {:>8} {:>10}", "not", "computed", "-");
      s += fmt::format("{:>4} {:>7.3f} {:>8.2f} {:>8.2f} {:>8.4f} {} {}\n", st.index + 1,
                       st.target_displacement_mm, p.t_s, p.t_window_s, q.displacement_mm, meas, pred);
      if (!q.computed && q.failure != failure) {
        failure = q.failure;
        s += fmt::format("     not computed from here: {}\n", failure);
      }
    }
  return s;
}

nlohmann::json to_json(const RunWaterCourse& c) {
  auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  const auto& o = c.options;
  nlohmann::json steps = nlohmann::json::array();
  for (const auto& st : c.steps) {
    nlohmann::json pts = nlohmann::json::array();
    for (const auto& p : st.points) {
      const auto& q = p.predicted;
      nlohmann::json j = {{"t_s", p.t_s},
                          {"t_window_s", p.t_window_s},
                          {"displacement_mm", q.displacement_mm},
                          {"measured_T", num(p.measured.T)},
                          {"measured_T_se", num(p.measured.se)},
                          {"measured_samples", p.measured.n},
                          {"computed", q.computed}};
      if (q.computed) {
        j["predicted_T"] = num(p.T);
        j["predicted_T_se"] = num(p.T_se);
        j["pin_force_N"] = num(q.pin_force_N);
        j["water_outflow_mm3"] = num(q.water_outflow_mm3);
      } else {
        j["failure"] = q.failure;
      }
      j["fe_seconds"] = q.fe_seconds;
      j["mesh_seconds"] = q.mesh_seconds;
      j["mc_seconds"] = q.mc_seconds;
      pts.push_back(j);
    }
    steps.push_back({{"step", st.index + 1},
                     {"displacement_mm", st.target_displacement_mm},
                     {"window_s", {st.window_from_s, st.window_to_s}},
                     {"points", pts}});
  }
  return {{"run", c.run_id},
          {"optics", "water"},
          {"quantity", "T(t) / T(glass-only baseline)"},
          {"config",
           {{"thickness_mm", c.thickness_mm},
            {"pin_radius_mm", o.pin_radius_mm},
            {"drained_poisson", o.drained_poisson},
            {"k0_mm4_per_Ns", o.k0_mm4_per_Ns},
            {"photons", o.photons},
            {"seed", o.seed},
            {"mesh", o.mesh_preset},
            {"points_per_hold", o.points_per_hold},
            {"window_s", o.window_s},
            {"fe_budget_s", o.fe_budget_s}}},
          {"history",
           {{"knots", c.history.history.t_s.size()},
            {"samples", c.history.samples},
            {"tolerance_mm", c.history.tolerance_mm},
            {"duration_s", c.history.history.t_s.back()}}},
          {"baseline", {{"T_glass", c.baseline_T}, {"T_glass_se", c.baseline_T_se}}},
          {"steps", steps},
          {"seconds", c.seconds}};
}

}  // namespace tocd::analysis

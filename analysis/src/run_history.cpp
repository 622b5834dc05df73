// A recorded run as time histories (run_history.hpp).
#include "tocd/analysis/run_history.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "tocd/core/error.hpp"

namespace tocd::analysis {

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  if (x.empty()) return std::numeric_limits<double>::quiet_NaN();
  if (at <= x.front()) return y.front();
  if (at >= x.back()) return y.back();
  const auto k = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), at) - x.begin());
  const double w = (at - x[k - 1]) / (x[k] - x[k - 1]);
  return y[k - 1] + w * (y[k] - y[k - 1]);
}

namespace {

std::size_t first_at_or_after(const std::vector<double>& t, double at) {
  return static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), at) - t.begin());
}

// The baseline the step table's T is relative to: the run's, or else the one its steps imply.
double baseline_power_W(const db::RunRecord& run, const std::vector<db::StepRecord>& steps,
                        std::int64_t power_channel) {
  if (std::isfinite(run.baseline_power_W) && run.baseline_power_W > 0) return run.baseline_power_W;
  for (const auto& s : steps) {
    const db::ChannelStats* p = s.stats_for(power_channel);
    if (s.completed && p && std::isfinite(p->mean) && std::isfinite(s.measured_transmission) &&
        s.measured_transmission > 0)
      return p->mean / s.measured_transmission;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

double sample_thickness_mm(const db::Reader& reader, const db::RunRecord& run) {
  const auto specimen = run.sample_id != 0 ? reader.sample(run.sample_id) : std::nullopt;
  if (!specimen || !(specimen->thickness_mm > 0))
    throw Error(fmt::format("run {} has no sample thickness: the FE cannot model it", run.id));
  return specimen->thickness_mm;
}

RunHistory read_run_history(const db::Reader& reader, std::int64_t run_id) {
  const db::RunRecord run = reader.run(run_id);
  RunHistory h;
  h.run_id = run_id;
  h.thickness_mm = sample_thickness_mm(reader, run);
  if (reader.anchors(run_id).size() > 1)
    throw Error(
        fmt::format("run {} was resumed after an interruption: the load history across the gap is "
                    "unknown, and the viscoelastic model needs all of it",
                    run_id));
  const auto load = reader.channel(run_id, "load");
  const auto disp = reader.channel(run_id, "displacement");
  if (!load || !disp)
    throw Error(fmt::format("run {} has no tester readings (load and displacement)", run_id));
  const auto loads = reader.samples(load->id);
  const auto disps = reader.samples(disp->id);
  if (loads.size() != disps.size())
    throw Error(fmt::format("run {}: {} load readings but {} displacement readings; they must pair up",
                            run_id, loads.size(), disps.size()));
  const double t0 = static_cast<double>(run.monotonic_anchor_ns);
  for (std::size_t k = 0; k < loads.size(); ++k) {
    if (loads[k].t_ns != disps[k].t_ns)
      throw Error(
          fmt::format("run {}: load and displacement reading {} were taken at different times", run_id, k));
    if (!std::isfinite(loads[k].value) || !std::isfinite(disps[k].value)) continue;
    const double t = (static_cast<double>(loads[k].t_ns) - t0) * 1e-9;
    if (!h.tester_t_s.empty() && t < h.tester_t_s.back())
      throw Error(fmt::format("run {}: tester readings go back in time at reading {}", run_id, k));
    h.tester_t_s.push_back(t);
    h.displacement_mm.push_back(std::max(0.0, disps[k].value));
    h.load_N.push_back(loads[k].value);
  }
  if (h.tester_t_s.size() < 2) throw Error(fmt::format("run {} has fewer than two tester readings", run_id));

  const auto steps = reader.steps(run_id);
  const auto power = reader.channel(run_id, "power");
  const double baseline = power ? baseline_power_W(run, steps, power->id) : std::nan("");
  if (power && std::isfinite(baseline)) {
    for (const auto& s : reader.samples(power->id)) {
      if (!std::isfinite(s.value)) continue;
      h.power_t_s.push_back((static_cast<double>(s.t_ns) - t0) * 1e-9);
      h.transmission.push_back(s.value / baseline);
    }
  }

  for (const auto& s : steps) {
    if (!s.completed || !std::isfinite(s.target_displacement_mm)) continue;
    const db::ChannelStats* d = s.stats_for(disp->id);
    if (!d || !std::isfinite(d->mean)) continue;
    Hold hold;
    hold.step_index = s.index;
    hold.displacement_mm = std::max(0.0, d->mean);
    hold.measured_transmission = s.measured_transmission;
    const double started = (static_cast<double>(s.started_t_ns) - t0) * 1e-9;
    const double from = (static_cast<double>(s.recorded_from_t_ns) - t0) * 1e-9;
    const double to = (static_cast<double>(s.recorded_to_t_ns) - t0) * 1e-9;
    hold.record_first = first_at_or_after(h.tester_t_s, from);
    std::size_t last = first_at_or_after(h.tester_t_s, to);
    if (last == h.tester_t_s.size() || h.tester_t_s[last] > to) --last;
    // The move ends at the last reading before the window that is off the held displacement
    // (by more than the reading scatter at rest: 1 um); the hold begins after it.
    std::size_t first = first_at_or_after(h.tester_t_s, started);
    for (std::size_t k = hold.record_first; k > first; --k)
      if (std::abs(h.displacement_mm[k - 1] - hold.displacement_mm) > 1e-3) {
        first = k;
        break;
      }
    if (hold.record_first >= h.tester_t_s.size() || last < hold.record_first) continue;
    hold.first = first;
    hold.last = last;
    h.holds.push_back(hold);
  }
  if (h.holds.empty()) throw Error(fmt::format("run {} has no completed pin step to identify from", run_id));
  return h;
}

}  // namespace tocd::analysis

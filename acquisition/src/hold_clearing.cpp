// Clearing during the holds, from the power recorded at 10 Hz through each step's window.
#include "tocd/acquisition/hold_clearing.hpp"

#include <cmath>

#include <fmt/format.h>

#include "tocd/core/error.hpp"
#include "tocd/core/running_stats.hpp"

namespace tocd::acquisition {

namespace {

struct Mean {
  double mean = 0, se = 0;
  std::int64_t n = 0;
};

Mean mean_of(const db::Reader& reader, std::int64_t channel, std::int64_t from_ns, std::int64_t to_ns) {
  db::SampleQuery q;
  q.from_t_ns = from_ns;
  q.to_t_ns = to_ns;
  RunningStats s;
  for (const auto& x : reader.samples(channel, q)) s.add(x.value);
  if (s.n() == 0) return {};
  return {s.mean(), s.n() > 1 ? s.std() / std::sqrt(static_cast<double>(s.n())) : 0.0, s.n()};
}

}  // namespace

std::vector<HoldClearing> hold_clearing(const db::Reader& reader, std::int64_t run_id, double window_s) {
  const auto run = reader.run(run_id);
  const auto power = reader.channel(run_id, "power");
  if (!power)
    throw tocd::Error(fmt::format("run {}: no power channel, so no transmission over time", run_id));
  if (!(run.baseline_power_W > 0))
    throw tocd::Error(fmt::format("run {}: no baseline power, so no transmission over time", run_id));
  const double P0 = run.baseline_power_W;
  const auto w = static_cast<std::int64_t>(window_s * 1e9);
  std::vector<HoldClearing> out;
  for (const auto& step : reader.steps(run_id)) {
    if (!step.completed || step.recorded_to_t_ns <= step.recorded_from_t_ns) continue;
    const std::int64_t a = step.recorded_from_t_ns, b = step.recorded_to_t_ns;
    const Mean first = mean_of(reader, power->id, a, std::min(b, a + w));
    const Mean last = mean_of(reader, power->id, std::max(a, b - w), b);
    if (first.n == 0 || last.n == 0) continue;
    HoldClearing h;
    h.index = step.index;
    h.displacement_mm = step.target_displacement_mm;
    h.window_s = static_cast<double>(b - a) * 1e-9;
    h.T_start = first.mean / P0;
    h.T_end = last.mean / P0;
    h.T_start_se = first.se / P0;
    h.T_end_se = last.se / P0;
    h.dT = h.T_end - h.T_start;
    h.dT_se = std::hypot(h.T_start_se, h.T_end_se);
    out.push_back(h);
  }
  return out;
}

std::string format_hold_clearing(const std::vector<HoldClearing>& rows) {
  std::string s = fmt::format("{:>4} {:>7} {:>8} {:>9} {:>9} {:>9} {:>8}\n", "step", "d_mm", "window_s",
                              "T_start", "T_end", "dT", "+-");
  for (const auto& h : rows)
    s += fmt::format("{:>4} {:>7.3f} {:>8.2f} {:>9.4f} {:>9.4f} {:>+9.4f} {:>8.4f}\n", h.index + 1,
                     h.displacement_mm, h.window_s, h.T_start, h.T_end, h.dT, h.dT_se);
  return s;
}

nlohmann::json hold_clearing_json(const std::vector<HoldClearing>& rows) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& h : rows)
    a.push_back({{"step", h.index + 1},
                 {"displacement_mm", h.displacement_mm},
                 {"window_s", h.window_s},
                 {"T_start", h.T_start},
                 {"T_start_se", h.T_start_se},
                 {"T_end", h.T_end},
                 {"T_end_se", h.T_end_se},
                 {"dT", h.dT},
                 {"dT_se", h.dT_se}});
  return a;
}

}  // namespace tocd::acquisition

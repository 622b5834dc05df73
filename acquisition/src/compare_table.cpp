#include "tocd/acquisition/compare_table.hpp"

#include <cmath>

#include <fmt/format.h>

#include "tocd/core/printable.hpp"

namespace tocd::acquisition {

CompareTable compare_table(const db::Reader& reader, std::int64_t run_id) {
  CompareTable t;
  const db::RunRecord run = reader.run(run_id);
  t.run_id = run_id;
  t.run_name = printable_text(run.name);  // from a protocol file: no raw controls on a terminal
  t.status = std::string(db::to_string(reader.shown_status(run_id)));
  t.baseline_power_W = run.baseline_power_W;
  const auto load = reader.channel(run_id, "load");
  for (const auto& row : reader.compare(run_id)) {
    CompareLine l;
    l.index = row.step.index;
    l.completed = row.step.completed;
    l.displacement_mm = row.step.target_displacement_mm;
    l.nominal_strain = row.step.nominal_strain;
    l.pressure_kPa = row.step.target_pressure_kPa;
    const db::ChannelStats* s = load ? row.step.stats_for(load->id) : nullptr;
    l.load_N = s ? s->mean : db::kUnset;
    l.measured_T = row.step.measured_transmission;
    l.has_prediction = row.prediction.has_value();
    l.predicted_T = row.prediction ? row.prediction->T : db::kUnset;
    l.predicted_T_stderr = row.prediction ? row.prediction->T_stderr : db::kUnset;
    l.relative_difference = row.relative_difference;
    if (!l.completed) {
      // A step cut short (older runs stored such rows) is not a measurement: no value of it is shown.
      l.load_N = l.measured_T = l.relative_difference = db::kUnset;
    }
    t.lines.push_back(l);
  }
  return t;
}

namespace {
std::string num(double v, const char* fmt_spec, int width) {
  if (!std::isfinite(v)) return fmt::format("{:>{}}", "-", width);
  return fmt::format(fmt::runtime(fmt::format("{{:>{}{}}}", width, fmt_spec)), v);
}
}  // namespace

std::string format_compare_table(const CompareTable& t) {
  std::string out = fmt::format("run {} \"{}\" ({}), baseline {:.6g} W\n", t.run_id, t.run_name, t.status,
                                t.baseline_power_W);
  const bool vacuum = !t.lines.empty() && std::isfinite(t.lines.front().pressure_kPa);
  out += fmt::format("{:>4}  {:>9}  {:>7}  {:>9}  {:>10}  {:>21}  {:>9}\n", "step",
                     vacuum ? "vac [kPa]" : "d [mm]", vacuum ? "" : "strain", "load [N]", "measured T",
                     "predicted T +- err", "rel diff");
  for (const auto& l : t.lines) {
    std::string pred = l.has_prediction && std::isfinite(l.predicted_T)
                           ? fmt::format("{:.5f} +- {:.5f}", l.predicted_T, l.predicted_T_stderr)
                           : std::string("-");
    std::string rel = std::isfinite(l.relative_difference)
                          ? fmt::format("{:+.2f} %", 100.0 * l.relative_difference)
                          : std::string("-");
    out +=
        fmt::format("{:>4}  {}  {}  {}  {}  {:>21}  {:>9}{}\n", l.index + 1,
                    num(vacuum ? l.pressure_kPa : l.displacement_mm, ".3f", 9),
                    vacuum ? std::string(7, ' ') : num(l.nominal_strain, ".3f", 7), num(l.load_N, ".4f", 9),
                    num(l.measured_T, ".5f", 10), pred, rel, l.completed ? "" : "  (cut short)");
  }
  return out;
}

nlohmann::json to_json(const CompareTable& t) {
  auto v = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  nlohmann::json j;
  j["run"] = {{"id", t.run_id},
              {"name", t.run_name},
              {"status", t.status},
              {"baseline_power_W", v(t.baseline_power_W)}};
  j["steps"] = nlohmann::json::array();
  for (const auto& l : t.lines) {
    j["steps"].push_back({{"index", l.index},
                          {"completed", l.completed},
                          {"displacement_mm", v(l.displacement_mm)},
                          {"nominal_strain", v(l.nominal_strain)},
                          {"pressure_kPa", v(l.pressure_kPa)},
                          {"load_N", v(l.load_N)},
                          {"measured_T", v(l.measured_T)},
                          {"predicted_T", v(l.predicted_T)},
                          {"predicted_T_se", v(l.predicted_T_stderr)},
                          {"relative_difference", v(l.relative_difference)}});
  }
  return j;
}

std::string format_compare_csv(const CompareTable& t) {
  auto v = [](double x) { return std::isfinite(x) ? fmt::format("{:.9g}", x) : std::string(); };
  std::string out =
      "step,displacement_mm,nominal_strain,pressure_kPa,load_N,measured_T,predicted_T,predicted_T_se,"
      "relative_difference,completed\n";
  for (const auto& l : t.lines) {
    const bool pred = l.has_prediction;
    out +=
        fmt::format("{},{},{},{},{},{},{},{},{},{}\n", l.index + 1, v(l.displacement_mm), v(l.nominal_strain),
                    v(l.pressure_kPa), v(l.load_N), v(l.measured_T), pred ? v(l.predicted_T) : "",
                    pred ? v(l.predicted_T_stderr) : "", v(l.relative_difference), l.completed ? 1 : 0);
  }
  return out;
}

}  // namespace tocd::acquisition

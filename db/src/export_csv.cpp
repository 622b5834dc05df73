#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "tocd/core/clock.hpp"
#include "tocd/db/export.hpp"

namespace tocd::db {

namespace {

// RFC 4180: quote fields holding a comma, quote, or line break; double embedded quotes.
std::string field(std::string_view s) {
  if (s.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(s);
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"') out += '"';
    out += ch;
  }
  return out + '"';
}

std::string num(double v) {
  return std::isnan(v) ? std::string() : fmt::format("{}", v);
}

void write_row(std::ostream& out, const std::vector<std::string>& cells) {
  for (std::size_t i = 0; i < cells.size(); ++i) out << (i ? "," : "") << cells[i];
  out << '\n';  // LF, as every CSV tocdlab writes
}

// Steps store no segment: a step belongs to the latest segment whose anchor is at or before
// the start of its motion on the monotonic clock (exact unless the machine rebooted).
int segment_of_step(const std::vector<RunAnchor>& anchors, const StepRecord& s) {
  int segment = 0;
  for (const auto& a : anchors)
    if (a.monotonic_ns <= s.started_t_ns) segment = a.segment;
  return segment;
}

// Standard error of the mean power over the recording window, relative to the baseline
// (readings taken as independent); the same formula as the step_comparison view.
double measured_T_se(const StepRecord& s, std::int64_t power_channel, double baseline_W) {
  const ChannelStats* p = s.stats_for(power_channel);
  if (!s.completed || !p || p->n < 2 || !(baseline_W > 0)) return kUnset;
  return p->std / std::sqrt(static_cast<double>(p->n)) / baseline_W;
}

void steps_csv(const Reader& reader, std::int64_t run_id, std::ostream& out) {
  const RunRecord run = reader.run(run_id);
  const auto channels = reader.channels(run_id);
  const auto anchors = reader.anchors(run_id);
  std::vector<std::string> head = {
      "step",      "completed",       "target_displacement_mm", "nominal_strain", "target_pressure_kPa",
      "settled_s", "recorded_from_s", "recorded_to_s"};
  for (const auto& ch : channels) {
    const std::string u = ch.unit.empty() ? "" : "_" + ch.unit;
    head.push_back(field(ch.name + "_mean" + u));
    head.push_back(field(ch.name + "_std" + u));
    head.push_back(field(ch.name + "_n"));
  }
  for (const char* h :
       {"measured_T", "measured_T_se", "predicted_T", "predicted_T_se", "relative_difference"})
    head.push_back(h);
  write_row(out, head);
  // Times in seconds since the run started, on the UTC axis: a step recorded after a resume
  // is placed by the anchor of the segment its recording began in.
  const auto rel = [&](std::int64_t t, int segment) {
    return t == 0 ? std::string()
                  : fmt::format("{:.6f}",
                                static_cast<double>(utc_ns(anchors, segment, t) - run.started_utc_ns) * 1e-9);
  };
  const std::int64_t power_channel = [&] {
    for (const auto& ch : channels)
      if (ch.name == "power") return ch.id;
    return std::int64_t{0};
  }();
  for (const auto& row : reader.compare(run_id)) {
    const StepRecord& s = row.step;
    const int segment = segment_of_step(anchors, s);
    std::vector<std::string> cells = {std::to_string(s.index + 1),        s.completed ? "1" : "0",
                                      num(s.target_displacement_mm),      num(s.nominal_strain),
                                      num(s.target_pressure_kPa),         rel(s.settled_t_ns, segment),
                                      rel(s.recorded_from_t_ns, segment), rel(s.recorded_to_t_ns, segment)};
    for (const auto& ch : channels) {
      const ChannelStats* cs = s.stats_for(ch.id);
      cells.push_back(cs ? num(cs->mean) : "");
      cells.push_back(cs ? num(cs->std) : "");
      cells.push_back(cs ? std::to_string(cs->n) : "");
    }
    cells.push_back(num(s.measured_transmission));
    cells.push_back(num(measured_T_se(s, power_channel, run.baseline_power_W)));
    cells.push_back(row.prediction ? num(row.prediction->T) : "");
    cells.push_back(row.prediction ? num(row.prediction->T_stderr) : "");
    cells.push_back(num(row.relative_difference));
    write_row(out, cells);
  }
}

void samples_csv(const Reader& reader, std::int64_t run_id, std::ostream& out) {
  const RunRecord run = reader.run(run_id);
  const auto anchors = reader.anchors(run_id);
  write_row(out, {"t_ns", "segment", "t_s", "utc", "channel", "unit", "value"});
  for (const auto& ch : reader.channels(run_id)) {
    const std::string name = field(ch.name), unit = field(ch.unit);
    for (const auto& s : reader.samples(ch.id)) {
      const std::int64_t utc = utc_ns(anchors, s.segment, s.t_ns);
      write_row(out, {std::to_string(s.t_ns), std::to_string(s.segment),
                      fmt::format("{:.9f}", static_cast<double>(utc - run.started_utc_ns) * 1e-9),
                      format_utc(utc), name, unit, num(s.value)});
    }
  }
}

void events_csv(const Reader& reader, std::int64_t run_id, std::ostream& out) {
  const auto anchors = reader.anchors(run_id);
  write_row(out, {"t_ns", "segment", "utc", "kind", "step", "message"});
  for (const auto& e : reader.events(run_id))
    write_row(out, {std::to_string(e.t_ns), std::to_string(e.segment),
                    format_utc(utc_ns(anchors, e.segment, e.t_ns)), field(e.kind),
                    e.step_index >= 0 ? std::to_string(e.step_index + 1) : "", field(e.message)});
}

}  // namespace

void write_csv(const Reader& reader, std::int64_t run_id, CsvTable table, std::ostream& out) {
  switch (table) {
    case CsvTable::steps:
      steps_csv(reader, run_id, out);
      break;
    case CsvTable::samples:
      samples_csv(reader, run_id, out);
      break;
    case CsvTable::events:
      events_csv(reader, run_id, out);
      break;
  }
}

}  // namespace tocd::db

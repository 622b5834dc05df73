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
  out << "\r\n";
}

void steps_csv(const Reader& reader, std::int64_t run_id, std::ostream& out) {
  const RunRecord run = reader.run(run_id);
  const auto channels = reader.channels(run_id);
  std::vector<std::string> head = {
      "step",      "completed",       "target_displacement_mm", "nominal_strain", "target_pressure_kPa",
      "settled_s", "recorded_from_s", "recorded_to_s"};
  for (const auto& ch : channels) {
    const std::string u = ch.unit.empty() ? "" : "_" + ch.unit;
    head.push_back(field(ch.name + "_mean" + u));
    head.push_back(field(ch.name + "_std" + u));
    head.push_back(field(ch.name + "_n"));
  }
  for (const char* h : {"measured_T", "predicted_T", "predicted_T_stderr", "relative_difference"})
    head.push_back(h);
  write_row(out, head);
  // Times in seconds since the run's monotonic anchor (the run start).
  const auto rel = [&](std::int64_t t) {
    return t == 0 ? std::string()
                  : fmt::format("{:.6f}", static_cast<double>(t - run.monotonic_anchor_ns) * 1e-9);
  };
  for (const auto& row : reader.compare(run_id)) {
    const StepRecord& s = row.step;
    std::vector<std::string> cells = {std::to_string(s.index),       s.completed ? "1" : "0",
                                      num(s.target_displacement_mm), num(s.nominal_strain),
                                      num(s.target_pressure_kPa),    rel(s.settled_t_ns),
                                      rel(s.recorded_from_t_ns),     rel(s.recorded_to_t_ns)};
    for (const auto& ch : channels) {
      const ChannelStats* cs = s.stats_for(ch.id);
      cells.push_back(cs ? num(cs->mean) : "");
      cells.push_back(cs ? num(cs->std) : "");
      cells.push_back(cs ? std::to_string(cs->n) : "");
    }
    cells.push_back(num(s.measured_transmission));
    cells.push_back(row.prediction ? num(row.prediction->T) : "");
    cells.push_back(row.prediction ? num(row.prediction->T_stderr) : "");
    cells.push_back(num(row.relative_difference));
    write_row(out, cells);
  }
}

void samples_csv(const Reader& reader, std::int64_t run_id, std::ostream& out) {
  const RunRecord run = reader.run(run_id);
  write_row(out, {"t_ns", "t_s", "utc", "channel", "unit", "value"});
  for (const auto& ch : reader.channels(run_id)) {
    const std::string name = field(ch.name), unit = field(ch.unit);
    for (const auto& s : reader.samples(ch.id)) {
      write_row(out, {std::to_string(s.t_ns),
                      fmt::format("{:.9f}", static_cast<double>(s.t_ns - run.monotonic_anchor_ns) * 1e-9),
                      format_utc(run.to_utc_ns(s.t_ns)), name, unit, num(s.value)});
    }
  }
}

void events_csv(const Reader& reader, std::int64_t run_id, std::ostream& out) {
  const RunRecord run = reader.run(run_id);
  write_row(out, {"t_ns", "utc", "kind", "step", "message"});
  for (const auto& e : reader.events(run_id))
    write_row(out, {std::to_string(e.t_ns), format_utc(run.to_utc_ns(e.t_ns)), field(e.kind),
                    e.step_index >= 0 ? std::to_string(e.step_index) : "", field(e.message)});
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

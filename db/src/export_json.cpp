#include <nlohmann/json.hpp>

#include "tocd/core/clock.hpp"
#include "tocd/db/export.hpp"

namespace tocd::db {

namespace {

using nlohmann::json;

// nlohmann writes NaN as null, which is what an unset value should read as.
json utc_or_null(const std::optional<std::int64_t>& t) {
  return t ? json(format_utc(*t)) : json(nullptr);
}

json run_json(const RunRecord& r) {
  return {{"id", r.id},
          {"uuid", r.uuid},
          {"name", r.name},
          {"status", std::string(to_string(r.status))},
          {"operator", r.operator_name},
          {"software_version", r.software_version},
          {"software_commit", r.software_commit},
          {"host", r.host},
          {"settings", r.settings},
          {"started_utc", format_utc(r.started_utc_ns)},
          {"ended_utc", utc_or_null(r.ended_utc_ns)},
          {"started_utc_ns", r.started_utc_ns},
          {"ended_utc_ns", r.ended_utc_ns ? json(*r.ended_utc_ns) : json(nullptr)},
          {"wall_anchor_utc_ns", r.wall_anchor_utc_ns},
          {"monotonic_anchor_ns", r.monotonic_anchor_ns},
          {"clock_factor", r.clock_factor},
          {"baseline_power_W", r.baseline_power_W},
          {"protocol", r.protocol_text},
          {"lab_config", r.lab_config_text}};
}

json parsed_or_text(const std::string& text) {
  if (text.empty()) return nullptr;
  json j = json::parse(text, nullptr, false);
  return j.is_discarded() ? json(text) : j;
}

// Each channel with its instrument (listed once in `instruments`) and, when asked, its samples.
json channels_json(const Reader& reader, std::int64_t run_id, const JsonExportOptions& opt,
                   json& instruments) {
  json channels = json::array();
  for (const auto& ch : reader.channels(run_id)) {
    json c = {{"id", ch.id}, {"name", ch.name}, {"unit", ch.unit}, {"nominal_rate_Hz", ch.nominal_rate_Hz}};
    c["instrument_id"] = ch.instrument_id ? json(ch.instrument_id) : json(nullptr);
    if (ch.instrument_id) {
      if (auto in = reader.instrument(ch.instrument_id)) {
        json ij = {{"id", in->id},         {"kind", in->kind},         {"model", in->model},
                   {"serial", in->serial}, {"firmware", in->firmware}, {"calibration", in->calibration}};
        bool seen = false;
        for (const auto& x : instruments) seen = seen || x["id"] == in->id;
        if (!seen) instruments.push_back(ij);
      }
    }
    c["sample_count"] = reader.sample_count(ch.id);
    if (opt.include_samples) {
      SampleQuery q;
      if (opt.max_points_per_channel > 0) {
        q.decimation = Decimation::mean;
        q.max_points = opt.max_points_per_channel;
      }
      json t = json::array(), v = json::array(), seg = json::array();
      for (const auto& s : reader.samples(ch.id, q)) {
        t.push_back(s.t_ns);
        v.push_back(s.value);
        seg.push_back(s.segment);
      }
      c["decimated"] = opt.max_points_per_channel > 0 &&
                       t.size() < static_cast<std::size_t>(c["sample_count"].get<std::int64_t>());
      c["t_ns"] = std::move(t);
      c["value"] = std::move(v);
      c["segment"] = std::move(seg);  // anchor segment of each sample (UTC: see "anchors")
    }
    channels.push_back(std::move(c));
  }
  return channels;
}

json steps_json(const Reader& reader, std::int64_t run_id) {
  json steps = json::array();
  for (const auto& row : reader.compare(run_id)) {
    const StepRecord& s = row.step;
    json stats = json::array();
    for (const auto& cs : s.channels)
      stats.push_back({{"channel_id", cs.channel_id}, {"mean", cs.mean}, {"std", cs.std}, {"n", cs.n}});
    json j = {{"step", s.index + 1},
              {"completed", s.completed},
              {"target_displacement_mm", s.target_displacement_mm},
              {"nominal_strain", s.nominal_strain},
              {"target_pressure_kPa", s.target_pressure_kPa},
              {"started_t_ns", s.started_t_ns},
              {"settled_t_ns", s.settled_t_ns},
              {"recorded_from_t_ns", s.recorded_from_t_ns},
              {"recorded_to_t_ns", s.recorded_to_t_ns},
              {"measured_transmission", s.measured_transmission},
              {"channels", stats},
              {"predicted_T", row.prediction ? json(row.prediction->T) : json(nullptr)},
              {"predicted_T_se", row.prediction ? json(row.prediction->T_stderr) : json(nullptr)},
              {"relative_difference", row.relative_difference}};
    steps.push_back(std::move(j));
  }
  return steps;
}

json events_json(const Reader& reader, std::int64_t run_id, const std::vector<RunAnchor>& run_anchors) {
  json events = json::array();
  for (const auto& e : reader.events(run_id)) {
    events.push_back({{"t_ns", e.t_ns},
                      {"segment", e.segment},
                      {"utc", format_utc(utc_ns(run_anchors, e.segment, e.t_ns))},
                      {"kind", e.kind},
                      {"step", e.step_index >= 0 ? json(e.step_index + 1) : json(nullptr)},
                      {"message", e.message},
                      {"data", parsed_or_text(e.data_json)}});
  }
  return events;
}

json predictions_json(const Reader& reader, std::int64_t run_id) {
  json predictions = json::array();
  for (const auto& p : reader.predictions(run_id)) {
    predictions.push_back({{"id", p.id},
                           {"step", p.step_index + 1},
                           {"T", p.T},
                           {"T_se", p.T_stderr},
                           {"fe_seconds", p.fe_seconds},
                           {"mesh_seconds", p.mesh_seconds},
                           {"mc_seconds", p.mc_seconds},
                           {"total_seconds", p.total_seconds},
                           {"latency_s", p.latency_s},
                           {"software_version", p.software_version},
                           {"created_utc", format_utc(p.created_utc_ns)},
                           {"config", parsed_or_text(p.config_json)},
                           {"summary", parsed_or_text(p.summary_json)}});
  }
  return predictions;
}

}  // namespace

void write_json(const Reader& reader, std::int64_t run_id, const JsonExportOptions& opt, std::ostream& out) {
  const RunRecord run = reader.run(run_id);
  json doc;
  doc["format"] = "tocdlab-run";
  doc["format_version"] = 2;  // 2: 1-based steps, *_se names, segments, run metadata
  doc["run"] = run_json(run);
  if (run.sample_id != 0) {
    if (auto sp = reader.sample(run.sample_id))
      doc["sample"] = {{"id", sp->id},
                       {"name", sp->name},
                       {"tissue", sp->tissue},
                       {"thickness_mm", sp->thickness_mm},
                       {"notes", sp->notes}};
  }
  const auto run_anchors = reader.anchors(run_id);
  json anchors = json::array();
  for (const auto& a : run_anchors)
    anchors.push_back({{"segment", a.segment},
                       {"wall_utc_ns", a.wall_utc_ns},
                       {"monotonic_ns", a.monotonic_ns},
                       {"clock_factor", a.clock_factor}});
  doc["anchors"] = anchors;
  json instruments = json::array();
  json channels = channels_json(reader, run_id, opt, instruments);
  doc["instruments"] = instruments;
  doc["channels"] = std::move(channels);
  doc["steps"] = steps_json(reader, run_id);
  doc["events"] = events_json(reader, run_id, run_anchors);
  doc["predictions"] = predictions_json(reader, run_id);
  // Text in the file may predate the printable_text cleaning at the instrument drivers (or the
  // file came from elsewhere): invalid UTF-8 becomes U+FFFD instead of failing the export.
  out << doc.dump(opt.indent, ' ', false, json::error_handler_t::replace) << '\n';
}

}  // namespace tocd::db

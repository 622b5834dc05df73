// A recorded run as load/displacement data for the inverse FE fit (docs/fe.md, "Inverse FE fit").
#include "tocd/analysis/run_pin_data.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "tocd/analysis/run_history.hpp"
#include "tocd/analysis/run_stress_strain.hpp"
#include "tocd/core/enum_names.hpp"
#include "tocd/core/error.hpp"

namespace tocd::analysis {

namespace {
constexpr std::array<EnumName<RunLoadPoints>, 2> kLoadPointNames{
    {{RunLoadPoints::held, "held"}, {RunLoadPoints::loading, "loading"}}};
}  // namespace

RunLoadPoints parse_run_load_points(const std::string& s) {
  if (const auto p = value_of(kLoadPointNames, s)) return *p;
  throw ConfigError(fmt::format("load points '{}': expected {}", s, name_list(kLoadPointNames)));
}

const char* to_string(RunLoadPoints p) {
  return name_of(kLoadPointNames, p).data();  // the table's names are literals
}

namespace {

// One point per completed pin step in contact: the recording window's mean load at the mean
// displacement the tester reported (the target where it reported none).
void add_held_points(const db::Reader& reader, std::int64_t run_id, sim::fe::PinCompressionData& p) {
  const auto load = reader.channel(run_id, "load");
  if (!load) throw Error(fmt::format("run {} has no load channel (no tester)", run_id));
  const auto disp = reader.channel(run_id, "displacement");
  for (const auto& step : reader.steps(run_id)) {
    if (!step.completed) continue;
    const db::ChannelStats* f = step.stats_for(load->id);
    const db::ChannelStats* d = disp ? step.stats_for(disp->id) : nullptr;
    const double displacement = d && std::isfinite(d->mean) ? d->mean : step.target_displacement_mm;
    if (!f || !std::isfinite(f->mean) || !(displacement > 0) || !(f->mean > 0)) continue;
    if (!p.displacement_mm.empty() && displacement <= p.displacement_mm.back())
      throw Error(
          fmt::format("run {}: step {} at {} mm is not deeper than the step before; the held loads "
                      "of a run that goes back and forth are no single curve (use --points loading)",
                      run_id, step.index, displacement));
    p.displacement_mm.push_back(displacement);
    p.load_N.push_back(f->mean);
  }
}

void add_loading_points(const db::Reader& reader, std::int64_t run_id, double pin_radius_mm, std::size_t bins,
                        sim::fe::PinCompressionData& p) {
  const auto ss = stress_strain_from_run(reader, run_id, pin_radius_mm, bins);
  const double area = std::numbers::pi * pin_radius_mm * pin_radius_mm;
  for (std::size_t k = 0; k < ss.strain.size(); ++k) {
    p.displacement_mm.push_back(ss.strain[k] * ss.thickness_mm);
    p.load_N.push_back(ss.stress_MPa[k] * area);
  }
}

}  // namespace

sim::fe::PinCompressionData pin_data_from_run(const db::Reader& reader, std::int64_t run_id,
                                              RunLoadPoints points, double pin_radius_mm, std::size_t bins,
                                              double thickness_mm) {
  if (!(pin_radius_mm > 0)) throw ConfigError(fmt::format("pin radius {} mm must be > 0", pin_radius_mm));
  sim::fe::PinCompressionData p;
  p.name = fmt::format("run {} ({} loads)", run_id, to_string(points));
  const double recorded = sample_thickness_mm(reader, reader.run(run_id));
  p.model.thickness_mm = thickness_mm > 0 ? thickness_mm : recorded;
  p.model.pin_radius_mm = pin_radius_mm;
  if (points == RunLoadPoints::held)
    add_held_points(reader, run_id, p);
  else
    add_loading_points(reader, run_id, pin_radius_mm, bins, p);
  if (p.displacement_mm.size() < 2)
    throw Error(fmt::format("run {}: only {} {} load points in contact (need 2) for a fit", run_id,
                            p.displacement_mm.size(), to_string(points)));
  return p;
}

}  // namespace tocd::analysis

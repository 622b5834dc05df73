#include "tocd/analysis/run_stress_strain.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "tocd/core/error.hpp"

namespace tocd::analysis {

RunStressStrain stress_strain_from_run(const db::Reader& reader, std::int64_t run_id, double pin_radius_mm,
                                       std::size_t bins, std::size_t min_points) {
  if (!(pin_radius_mm > 0)) throw ConfigError(fmt::format("pin radius {} mm must be > 0", pin_radius_mm));
  if (bins < 1) throw ConfigError("stress-strain binning needs at least one bin");
  const db::RunRecord run = reader.run(run_id);
  const auto specimen = run.sample_id != 0 ? reader.sample(run.sample_id) : std::nullopt;
  if (!specimen || !(specimen->thickness_mm > 0))
    throw Error(fmt::format("run {} has no sample thickness: strain cannot be computed", run_id));
  const auto d_ch = reader.channel(run_id, "displacement");
  const auto f_ch = reader.channel(run_id, "load");
  if (!d_ch || !f_ch)
    throw Error(fmt::format("run {} has no displacement and load channels (no tester)", run_id));
  const std::vector<db::Sample> d = reader.samples(d_ch->id);
  const std::vector<db::Sample> f = reader.samples(f_ch->id);

  RunStressStrain out;
  out.thickness_mm = specimen->thickness_mm;
  out.pin_radius_mm = pin_radius_mm;
  const double area_mm2 = std::numbers::pi * pin_radius_mm * pin_radius_mm;
  std::vector<double> sum(bins, 0.0), strain_sum(bins, 0.0);
  std::vector<std::size_t> n(bins, 0);
  double deepest = 0;
  // Both channels come from one reading each poll: merge on equal timestamps.
  std::size_t i = 0, j = 0;
  while (i < d.size() && j < f.size()) {
    if (d[i].t_ns < f[j].t_ns) {
      ++i;
      continue;
    }
    if (f[j].t_ns < d[i].t_ns) {
      ++j;
      continue;
    }
    const double disp = d[i].value, load = f[j].value;
    ++i;
    ++j;
    if (!std::isfinite(disp) || !std::isfinite(load) || disp <= 0) continue;
    // Only readings at a new deepest point: holds (load relaxing at constant depth),
    // pauses and the retraction would bias the loading curve.
    if (disp <= deepest) continue;
    deepest = disp;
    const double strain = disp / out.thickness_mm;
    if (strain >= 1) continue;
    const auto b = std::min(bins - 1, static_cast<std::size_t>(strain * static_cast<double>(bins)));
    sum[b] += load / area_mm2;
    strain_sum[b] += strain;
    ++n[b];
    ++out.pairs_used;
  }
  for (std::size_t b = 0; b < bins; ++b) {
    if (n[b] == 0) continue;
    out.strain.push_back(strain_sum[b] / static_cast<double>(n[b]));
    out.stress_MPa.push_back(std::max(0.0, sum[b] / static_cast<double>(n[b])));
  }
  if (out.strain.size() < min_points)
    throw Error(fmt::format("run {}: only {} strain levels with load in contact (need {}) for a fit", run_id,
                            out.strain.size(), min_points));
  return out;
}

}  // namespace tocd::analysis

// The sample's own law next to the default one, step by step (docs/study.md, "Sample's own law").
#include "tocd/analysis/fitted_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tocd/acquisition/compare_table.hpp"
#include "tocd/analysis/run_pin_data.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/fe/inverse_fit.hpp"
#include "tocd/sim/material/stiffness_scale.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace tocd::analysis {
namespace {

namespace fe = tocd::sim::fe;
namespace mat = tocd::sim::material;
namespace st = tocd::sim::study;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void read_fit_file(const std::string& path, FittedComparison& out) {
  std::ifstream in(path);
  if (!in) throw tocd::ConfigError(fmt::format("--material {}: cannot open the file", path));
  try {
    auto fit = fe::fitted_laws_from_json(nlohmann::json::parse(in));
    out.law = fit.law;
    out.band_laws = std::move(fit.confidence_laws);
  } catch (const nlohmann::json::exception& e) {
    throw tocd::ConfigError(
        fmt::format("--material {}: expected 'fitted' or the output of `tocdlab fit --method fe --json` ({})",
                    path, e.what()));
  }
}

// `scaled`: one FE solve per evaluation, a handful of evaluations. It matches the held loads:
// the ones the step table shows next to the FE forces (run_pin_data.hpp says why not the curve).
void fit_here(const db::Reader& reader, std::int64_t run_id, const FittedComparisonOptions& o,
              FittedComparison& out) {
  const fe::PinCompressionData p = pin_data_from_run(reader, run_id, RunLoadPoints::held, o.pin_radius_mm);
  fe::InverseFitOptions fo;
  fo.model = fe::InverseModel::scaled;
  if (o.progress) fo.progress = [&](const std::string& s) { o.progress("fit: " + s); };
  const auto r = fe::fit_material({p}, {}, fo);
  out.law = r.material;
  out.band_laws = r.confidence_laws;
  out.fitted_here = true;
  out.factor = r.values[0];
  out.factor_low = r.interval_low[0];
  out.factor_high = r.interval_high[0];
  out.confidence = r.confidence;
}

// The identified sample: its stiffness scale (profile interval) on the published law, and its
// re-predicted steps. A run whose optics cannot be identified has no identified T to show.
void identify_here(const db::Reader& reader, std::int64_t run_id, const FittedComparisonOptions& o,
                   FittedComparison& out) {
  SampleIdentificationOptions io;
  io.mechanics.pin_radius_mm = o.pin_radius_mm;
  if (o.photons) io.monte_carlo.photons = o.photons;
  io.monte_carlo.threads = o.threads;
  io.monte_carlo.pin_radius_mm = o.pin_radius_mm;
  io.progress = o.progress;
  SampleIdentification id = identify_sample(reader, run_id, io);
  if (!id.optics)
    throw tocd::Error(fmt::format(
        "run {}: the sample's optics were not identified ({})", run_id,
        id.optics_not_identified.empty() ? "the run recorded no transmission" : id.optics_not_identified));
  const IdentifiedParameter& scale = id.mechanics.report.at("stiffness_scale");
  out.law = mat::scale_stiffness(st::published_skin_material(), scale.value);
  out.factor = scale.value;
  out.factor_low = scale.lo;
  out.factor_high = scale.hi;
  out.confidence = 0.95;
  out.fitted_here = true;
  out.identification = std::move(id);
}

struct Ratio {
  double T = kNaN, se = kNaN;
};

// T(step) / T(baseline) as the run engine computes it, for a stored config with another law.
Ratio predict(st::Predictor& predictor, st::ConfigDocument doc, const mat::OgdenParameters& law,
              const FittedComparisonOptions& o) {
  doc.step.material = law;
  auto apply = [&](st::PredictionRequest& r) {
    if (o.photons) r.photons = o.photons;
    r.threads = o.threads;
  };
  apply(doc.step);
  const auto s = predictor.predict(doc.step);
  if (!doc.baseline) return {s.T, s.T_stderr};
  apply(*doc.baseline);
  const auto b = predictor.predict(*doc.baseline);
  const double T = s.T / b.T;
  return {T, T * std::hypot(s.T_stderr / s.T, b.T_stderr / b.T)};
}

// The FE pin force at the step's displacement with `law` (NaN for the flat baseline).
double fe_force(const st::PredictionRequest& step, const mat::OgdenParameters& law) {
  if (step.displacement_mm <= 0) return kNaN;
  fe::PinCompressionData pc;
  pc.model.thickness_mm = step.thickness_mm;
  pc.model.pin_radius_mm = step.pin_radius_mm;
  pc.model.outer_radius_mm = 0.5 * step.slide_size_mm;
  pc.displacement_mm = {step.displacement_mm};
  pc.load_N = {0};
  const auto f = fe::pin_force_curve(pc, law);
  return f.empty() ? kNaN : f[0];
}

}  // namespace

FittedComparison compare_with_fitted_law(const db::Reader& reader, std::int64_t run_id,
                                         const FittedComparisonOptions& o) {
  const auto table = acquisition::compare_table(reader, run_id);
  std::map<int, std::string> configs;  // latest prediction config per step
  for (const auto& p : reader.predictions(run_id)) configs[p.step_index] = p.config_json;

  FittedComparison out;
  out.run_id = run_id;
  if (o.material == "fitted")
    fit_here(reader, run_id, o, out);
  else if (o.material == "identified")
    identify_here(reader, run_id, o, out);
  else
    read_fit_file(o.material, out);

  st::Predictor predictor(1);
  for (const auto& line : table.lines) {
    FittedStep s;
    s.index = line.index;
    s.displacement_mm = line.displacement_mm;
    s.nominal_strain = line.nominal_strain;
    s.load_N = line.load_N;
    s.measured_T = line.measured_T;
    s.T_default = line.has_prediction ? line.predicted_T : kNaN;
    s.T_default_se = line.has_prediction ? line.predicted_T_stderr : kNaN;
    s.fe_force_default_N = s.fe_force_fitted_N = kNaN;
    s.T_fitted = s.T_fitted_se = s.band_lo = s.band_hi = kNaN;
    const auto cfg = configs.find(line.index);
    if (out.identification) {
      for (const auto& step : out.identification->optics->steps) {
        if (step.step_index != line.index) continue;
        s.T_fitted = step.predicted_T;
        s.T_fitted_se = step.predicted_T_se;
        s.band_lo = step.band_lo;
        s.band_hi = step.band_hi;
      }
      if (cfg != configs.end()) {
        const auto doc = st::config_document_from_json(nlohmann::json::parse(cfg->second));
        s.fe_force_default_N = fe_force(doc.step, doc.step.material);
        s.fe_force_fitted_N = fe_force(doc.step, out.law);
      }
    } else if (cfg != configs.end()) {
      const auto doc = st::config_document_from_json(nlohmann::json::parse(cfg->second));
      if (o.progress)
        o.progress(fmt::format("step {}: d = {} mm, predicting with the fitted law", line.index,
                               doc.step.displacement_mm));
      s.fe_force_default_N = fe_force(doc.step, doc.step.material);
      s.fe_force_fitted_N = fe_force(doc.step, out.law);
      const Ratio fitted = predict(predictor, doc, out.law, o);
      s.T_fitted = fitted.T;
      s.T_fitted_se = fitted.se;
      s.band_lo = s.band_hi = fitted.T;
      for (const auto& [label, law] : out.band_laws) {
        const Ratio b = predict(predictor, doc, law, o);  // same seed: the band is not MC noise
        s.band_lo = std::min(s.band_lo, b.T);
        s.band_hi = std::max(s.band_hi, b.T);
      }
    }
    out.steps.push_back(s);
  }
  return out;
}

}  // namespace tocd::analysis

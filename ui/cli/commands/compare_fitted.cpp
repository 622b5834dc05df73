// The fitted-law branch of `tocdlab compare` (docs/study.md, "Sample's own law").
#include "compare_fitted.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tocd/acquisition/compare_table.hpp"
#include "tocd/acquisition/run_stress_strain.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/sim/fe/inverse_fit.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace tocd::cli {
namespace {

namespace fe = tocd::sim::fe;
namespace mat = tocd::sim::material;
namespace st = tocd::sim::study;
using Laws = std::vector<std::pair<std::string, mat::OgdenParameters>>;

mat::OgdenParameters law_from_json(const nlohmann::json& j) {
  mat::OgdenParameters p;
  p.mu = j.at("mu_MPa").get<std::vector<double>>();
  p.alpha = j.at("alpha").get<std::vector<double>>();
  p.D = j.at("D_per_MPa").get<std::vector<double>>();
  p.validate();
  return p;
}

// The law and its confidence laws: from a fit file, or fitted here (`scaled`: one FE solve
// per evaluation, a few evaluations).
mat::OgdenParameters sample_law(const CompareFittedOptions& o, const db::Reader& reader, Laws& band) {
  if (o.material != "fitted") {
    std::ifstream in(o.material);
    if (!in) throw tocd::ConfigError(fmt::format("--material {}: cannot open the file", o.material));
    try {
      const auto j = nlohmann::json::parse(in);
      for (const auto& c : j.at("confidence_laws"))
        band.emplace_back(c.at("label").get<std::string>(), law_from_json(c));
      return law_from_json(j.at("ogden"));
    } catch (const nlohmann::json::exception& e) {
      throw tocd::ConfigError(fmt::format(
          "--material {}: expected 'fitted' or the output of `tocdlab fit --method fe --json` ({})",
          o.material, e.what()));
    }
  }
  const auto ss = tocd::acquisition::stress_strain_from_run(reader, o.run, o.pin_radius, 16);
  fe::PinCompressionData p;
  p.name = fmt::format("run {}", o.run);
  p.model.thickness_mm = ss.thickness_mm;
  p.model.pin_radius_mm = o.pin_radius;
  const double area = std::numbers::pi * o.pin_radius * o.pin_radius;
  for (std::size_t k = 0; k < ss.strain.size(); ++k) {
    p.displacement_mm.push_back(ss.strain[k] * ss.thickness_mm);
    p.load_N.push_back(ss.stress_MPa[k] * area);
  }
  fe::InverseFitOptions fo;
  fo.model = fe::InverseModel::scaled;
  fo.progress = [](const std::string& s) { std::cerr << "fit: " << s << '\n'; };
  const auto r = fe::fit_material({p}, {}, fo);
  std::cerr << fmt::format(
      "run {}: fitted stiffness factor on the published law {:.4f} +- {:.4f} ({:.0f} %)\n", o.run,
      r.values[0], r.interval_high[0] - r.values[0], 100 * r.confidence);
  band = r.confidence_laws;
  return r.material;
}

struct Ratio {
  double T = std::numeric_limits<double>::quiet_NaN(), se = std::numeric_limits<double>::quiet_NaN();
};

// T(step) / T(baseline) as the run engine computes it, for a stored config with another law.
Ratio predict(st::Predictor& predictor, st::ConfigDocument doc, const mat::OgdenParameters& law,
              const CompareFittedOptions& o) {
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

}  // namespace

void run_compare_fitted(const CompareFittedOptions& o) {
  const db::Reader reader(o.db);
  const auto table = tocd::acquisition::compare_table(reader, o.run);
  std::map<int, std::string> configs;  // latest prediction config per step
  for (const auto& p : reader.predictions(o.run)) configs[p.step_index] = p.config_json;
  Laws band;
  const mat::OgdenParameters law = sample_law(o, reader, band);
  st::Predictor predictor(1);

  nlohmann::json steps = nlohmann::json::array();
  std::string text = fmt::format("{:>4} {:>7} {:>9} {:>9} {:>9} | {:>9} {:>9} {:>8} {:>9} {:>8} {:>21}\n",
                                 "step", "d_mm", "load_N", "F_default", "F_fitted", "meas_T", "T_default",
                                 "+-MC", "T_fitted", "+-MC", "model band");
  for (const auto& line : table.lines) {
    nlohmann::json j = {{"index", line.index}, {"displacement_mm", line.displacement_mm}};
    auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
    j["load_N"] = num(line.load_N);
    j["measured_T"] = num(line.measured_T);
    j["predicted_T_default"] = num(line.has_prediction ? line.predicted_T : NAN);
    j["predicted_T_default_se"] = num(line.has_prediction ? line.predicted_T_stderr : NAN);
    const auto cfg = configs.find(line.index);
    if (cfg == configs.end()) {
      steps.push_back(j);
      continue;
    }
    const auto doc = st::config_document_from_json(nlohmann::json::parse(cfg->second));
    std::cerr << fmt::format("step {}: d = {} mm, predicting with the fitted law\n", line.index,
                             doc.step.displacement_mm);
    // The FE force at this step with each law, next to the measured load.
    double F_default = NAN, F_fitted = NAN;
    if (doc.step.displacement_mm > 0) {
      fe::PinCompressionData pc;
      pc.model.thickness_mm = doc.step.thickness_mm;
      pc.model.pin_radius_mm = doc.step.pin_radius_mm;
      pc.model.outer_radius_mm = 0.5 * doc.step.slide_size_mm;
      pc.displacement_mm = {doc.step.displacement_mm};
      pc.load_N = {0};
      const auto fd = fe::pin_force_curve(pc, doc.step.material);
      const auto ff = fe::pin_force_curve(pc, law);
      if (!fd.empty()) F_default = fd[0];
      if (!ff.empty()) F_fitted = ff[0];
    }
    const Ratio fitted = predict(predictor, doc, law, o);
    double lo = fitted.T, hi = fitted.T;
    for (const auto& [label, l] : band) {
      const Ratio b = predict(predictor, doc, l, o);  // same seed: the band is not MC noise
      lo = std::min(lo, b.T);
      hi = std::max(hi, b.T);
    }
    j["fe_force_default_N"] = num(F_default);
    j["fe_force_fitted_N"] = num(F_fitted);
    j["predicted_T_fitted"] = num(fitted.T);
    j["predicted_T_fitted_se"] = num(fitted.se);
    j["model_band"] = {num(lo), num(hi)};
    steps.push_back(j);
    text += fmt::format(
        "{:>4} {:>7.3f} {:>9.4f} {:>9.4f} {:>9.4f} | {:>9.4f} {:>9.4f} {:>8.4f} {:>9.4f} {:>8.4f} {:>21}\n",
        line.index, line.displacement_mm, line.load_N, F_default, F_fitted, line.measured_T, line.predicted_T,
        line.predicted_T_stderr, fitted.T, fitted.se, fmt::format("[{:.4f}, {:.4f}]", lo, hi));
  }
  if (o.json) {
    std::cout << nlohmann::json{{"run", o.run},
                                {"material",
                                 {{"mu_MPa", law.mu}, {"alpha", law.alpha}, {"D_per_MPa", law.D}}},
                                {"band_laws", band.size()},
                                {"steps", steps}}
                     .dump(2)
              << '\n';
  } else {
    std::cout << fmt::format(
                     "run {}: default law (stored predictions) vs the sample's fitted law; model band over "
                     "{} confidence laws\n",
                     o.run, band.size())
              << text;
  }
}

}  // namespace tocd::cli

// The fitted-law branch of `tocdlab compare` (docs/study.md, "Sample's own law"): the numbers
// come from analysis::compare_with_fitted_law, this file lays them out.
#include "compare_fitted.hpp"

#include <cmath>
#include <iostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tocd/analysis/fitted_comparison.hpp"

namespace tocd::cli {

void run_compare_fitted(const CompareFittedOptions& o) {
  const db::Reader reader(o.db);
  analysis::FittedComparisonOptions fo;
  fo.material = o.material;
  fo.pin_radius_mm = o.pin_radius;
  fo.photons = o.photons;
  fo.threads = o.threads;
  fo.progress = [](const std::string& s) { std::cerr << s << '\n'; };
  const auto c = analysis::compare_with_fitted_law(reader, o.run, fo);
  const bool identified = c.identification.has_value();
  if (identified)
    std::cerr << fmt::format(
        "run {}: identified stiffness scale on the published law {:.4f} [{:.4f}, {:.4f}] (95 %)\n", o.run,
        c.factor, c.factor_low, c.factor_high);
  else if (c.fitted_here)
    std::cerr << fmt::format(
        "run {}: fitted stiffness factor on the published law {:.4f} +- {:.4f} ({:.0f} %)\n", o.run, c.factor,
        c.factor_high - c.factor, 100 * c.confidence);

  auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  if (o.json) {
    nlohmann::json steps = nlohmann::json::array();
    for (const auto& s : c.steps) {
      nlohmann::json j = {{"index", s.index},
                          {"displacement_mm", s.displacement_mm},
                          {"load_N", num(s.load_N)},
                          {"measured_T", num(s.measured_T)},
                          {"predicted_T_default", num(s.T_default)},
                          {"predicted_T_default_se", num(s.T_default_se)}};
      if (std::isfinite(s.T_fitted)) {
        j["fe_force_default_N"] = num(s.fe_force_default_N);
        j["fe_force_fitted_N"] = num(s.fe_force_fitted_N);
        j["predicted_T_fitted"] = num(s.T_fitted);
        j["predicted_T_fitted_se"] = num(s.T_fitted_se);
        j["model_band"] = {num(s.band_lo), num(s.band_hi)};
      }
      steps.push_back(j);
    }
    nlohmann::json doc{{"run", o.run},
                       {"material", {{"mu_MPa", c.law.mu}, {"alpha", c.law.alpha}, {"D_per_MPa", c.law.D}}},
                       {"band_laws", c.band_laws.size()},
                       {"steps", steps}};
    if (identified) {
      doc["band"] = "the identified optical parameters' 95 % band";
      doc["identification"] = analysis::to_json(*c.identification);
    }
    std::cout << doc.dump(2) << '\n';
    return;
  }
  if (identified)
    std::cout << fmt::format(
        "run {}: default law (stored predictions) vs the identified sample (stiffness x{:.3f}, its clearing "
        "optics and delay); band: the optical parameters' 95 %\n",
        o.run, c.factor);
  else
    std::cout << fmt::format(
        "run {}: default law (stored predictions) vs the sample's fitted law; model band over {} confidence "
        "laws\n",
        o.run, c.band_laws.size());
  std::cout << fmt::format("{:>4} {:>7} {:>9} {:>9} {:>9} | {:>9} {:>9} {:>8} {:>9} {:>8} {:>21}\n", "step",
                           "d_mm", "load_N", "F_default", "F_fitted", "meas_T", "T_default", "+-MC",
                           "T_fitted", "+-MC", "model band");
  for (const auto& s : c.steps) {
    if (!std::isfinite(s.T_fitted)) continue;  // no stored prediction to re-make
    std::cout << fmt::format(
        "{:>4} {:>7.3f} {:>9.4f} {:>9.4f} {:>9.4f} | {:>9.4f} {:>9.4f} {:>8.4f} {:>9.4f} {:>8.4f} {:>21}\n",
        s.index + 1, s.displacement_mm, s.load_N, s.fe_force_default_N, s.fe_force_fitted_N, s.measured_T,
        s.T_default, s.T_default_se, s.T_fitted, s.T_fitted_se,
        fmt::format("[{:.4f}, {:.4f}]", s.band_lo, s.band_hi));
  }
}

}  // namespace tocd::cli

#include "tocd/sim/study/sensitivity.hpp"

#include <algorithm>
#include <cmath>
#include <future>

#include <fmt/format.h>

#include "elapsed.hpp"
#include "tocd/core/error.hpp"

namespace tocd::sim::study {

namespace {

// Per-batch transmissions and the summed prediction of one request. Batches run `threads` at a
// time; each is the exact tally of that batch, so the sum equals one predict() call.
struct Batched {
  std::vector<double> T;
  Prediction total;
};

Batched run_batched(Predictor& predictor, const PredictionRequest& r) {
  const int B = r.batches;
  const int parallel =
      std::max(1, r.threads > 0 ? r.threads : static_cast<int>(std::thread::hardware_concurrency()));
  PredictionRequest one = r;
  one.threads = 1;
  std::vector<mc::Tallies> tallies(static_cast<std::size_t>(B));
  const auto t0 = Clock::now();
  for (int first = 0; first < B; first += parallel) {
    std::vector<std::future<mc::Tallies>> running;
    for (int b = first; b < std::min(B, first + parallel); ++b)
      running.push_back(
          std::async(std::launch::async, [&, b] { return predictor.run_batches(one, b, b + 1); }));
    for (int b = first; b < std::min(B, first + parallel); ++b) tallies[b] = running[b - first].get();
  }
  const double mc_seconds = seconds_since(t0);
  Batched out;
  mc::Tallies sum = tallies[0];
  for (int b = 0; b < B; ++b) {
    out.T.push_back(predictor.assemble(one, tallies[b], 0).T);
    if (b > 0)
      for (std::size_t w = 0; w < sum.words.size(); ++w) sum.words[w] += tallies[b].words[w];
  }
  out.total = predictor.assemble(one, sum, mc_seconds);
  return out;
}

}  // namespace

std::vector<SensitivityVariant> sensitivity_variants(
    const PredictionRequest& base,
    const std::vector<std::pair<std::string, tocd::sim::material::OgdenParameters>>& material_laws) {
  std::vector<SensitivityVariant> v;
  auto add = [&](const std::string& factor, const std::string& label, auto change) {
    SensitivityVariant s{factor, label, base};
    change(s.request);
    v.push_back(std::move(s));
  };
  add("FE kinematics", "plane stress",
      [](PredictionRequest& r) { r.fe_kinematics = fe::Kinematics::plane_stress; });
  add("FE kinematics", "plane strain",
      [](PredictionRequest& r) { r.fe_kinematics = fe::Kinematics::plane_strain; });
  add("FE sample half width", "4.5 mm", [](PredictionRequest& r) { r.fe_outer_radius_mm = 4.5; });
  add("skin bottom", "sliding", [](PredictionRequest& r) { r.fe_bottom = fe::Bottom::sliding; });
  for (double t : {-0.4, -0.6})
    add("compressed threshold", fmt::format("{} log strain", t),
        [t](PredictionRequest& r) { r.compressed_log_strain = t; });
  for (double dl : {-0.5, 0.5})
    add("pin length", fmt::format("{:.1f} mm", base.pin_length_mm + dl),
        [dl](PredictionRequest& r) { r.pin_length_mm += dl; });
  const std::string other = base.mesh_preset == "fast" ? "paper" : "fast";
  add("mesh preset", other, [&](PredictionRequest& r) { r.mesh_preset = other; });
  add("slide index", "1.52", [](PredictionRequest& r) { r.slide_n = 1.52; });
  add("optics model", base.optics_model == "graded" ? "threshold" : "graded",
      [](PredictionRequest& r) { r.optics_model = r.optics_model == "graded" ? "threshold" : "graded"; });
  for (const auto& [label, law] : material_laws)
    add("Ogden law (fit confidence)", label, [fitted = law](PredictionRequest& r) { r.material = fitted; });
  return v;
}

SensitivityTable run_sensitivity(Predictor& predictor, const PredictionRequest& base,
                                 const std::vector<SensitivityVariant>& variants,
                                 const std::function<void(const std::string&)>& progress) {
  validate(base);
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  const auto t0 = Clock::now();
  SensitivityTable table;
  table.base = base;
  const Batched b = run_batched(predictor, base);
  table.T = b.total.T;
  table.T_se = b.total.T_stderr;
  say(fmt::format("base: T = {:.6f} +- {:.6f} ({:.0f} s)", table.T, table.T_se, seconds_since(t0)));
  for (const auto& v : variants) {
    const auto t1 = Clock::now();
    if (v.request.seed != base.seed || v.request.photons != base.photons || v.request.batches != base.batches)
      throw tocd::ConfigError("sensitivity: every variant must keep the base's seed, photons and batches");
    SensitivityRow row;
    row.variant = v;
    try {
      const Batched r = run_batched(predictor, v.request);
      row.T = r.total.T;
      row.T_se = r.total.T_stderr;
      row.dT = r.total.T - table.T;
      // Standard error of the mean per-batch difference (batches are independent; within a
      // batch variant and base share their random numbers).
      const int B = static_cast<int>(r.T.size());
      double mean = 0, var = 0;
      for (int k = 0; k < B; ++k) mean += (r.T[k] - b.T[k]) / B;
      for (int k = 0; k < B; ++k) var += std::pow(r.T[k] - b.T[k] - mean, 2) / (B - 1);
      row.dT_se = std::sqrt(var / B);
      row.resolved = std::abs(row.dT) > 2 * row.dT_se;
    } catch (const tocd::Error& e) {
      say(fmt::format("{} = {}: not computed: {}", v.factor, v.label, e.what()));
      table.not_computed.push_back({v, e.what()});
      continue;
    }
    row.seconds = seconds_since(t1);
    say(fmt::format("{} = {}: T = {:.6f}, dT = {:+.6f} +- {:.6f} ({:.0f} s)", v.factor, v.label, row.T,
                    row.dT, row.dT_se, row.seconds));
    table.rows.push_back(std::move(row));
  }
  table.seconds = seconds_since(t0);
  return table;
}

std::string format_sensitivity(const SensitivityTable& t) {
  std::string s =
      fmt::format("base: d = {} mm, h = {} mm, {} optics, {} photons, seed {}: T = {:.6f} +- {:.6f}\n",
                  t.base.displacement_mm, t.base.thickness_mm, t.base.optics_model, t.base.photons,
                  t.base.seed, t.T, t.T_se);
  s += fmt::format("{:<28} {:<18} {:>10} {:>10} {:>10} {:>8}  {}\n", "factor", "value", "T", "dT", "dT_se",
                   "dT/T %", "resolved");
  for (const auto& r : t.rows)
    s += fmt::format("{:<28} {:<18} {:>10.6f} {:>+10.6f} {:>10.6f} {:>+8.2f}  {}\n", r.variant.factor,
                     r.variant.label, r.T, r.dT, r.dT_se, 100 * r.dT / t.T,
                     r.resolved ? "yes" : "below MC error");
  for (const auto& n : t.not_computed)
    s += fmt::format("{:<28} {:<18} not computed: {}\n", n.variant.factor, n.variant.label, n.reason);
  return s;
}

nlohmann::json to_json(const SensitivityTable& t) {
  nlohmann::json j;
  j["base"] = {{"T", t.T}, {"T_se", t.T_se}, {"config", to_config(t.base)}};
  auto rows = nlohmann::json::array();
  for (const auto& r : t.rows)
    rows.push_back({{"factor", r.variant.factor},
                    {"label", r.variant.label},
                    {"T", r.T},
                    {"T_se", r.T_se},
                    {"dT", r.dT},
                    {"dT_se", r.dT_se},
                    {"resolved", r.resolved},
                    {"seconds", r.seconds},
                    {"config", to_config(r.variant.request)}});
  j["rows"] = rows;
  std::vector<const SensitivityRow*> order;
  for (const auto& r : t.rows) order.push_back(&r);
  std::stable_sort(order.begin(), order.end(), [](const SensitivityRow* a, const SensitivityRow* b) {
    return std::abs(a->dT) > std::abs(b->dT);
  });
  auto tornado = nlohmann::json::array();
  for (const auto* r : order)
    tornado.push_back(
        {{"factor", r->variant.factor}, {"label", r->variant.label}, {"dT", r->dT}, {"dT_se", r->dT_se}});
  j["tornado"] = tornado;
  auto missing = nlohmann::json::array();
  for (const auto& n : t.not_computed)
    missing.push_back({{"factor", n.variant.factor}, {"label", n.variant.label}, {"reason", n.reason}});
  j["not_computed"] = missing;
  j["seconds"] = t.seconds;
  return j;
}

}  // namespace tocd::sim::study

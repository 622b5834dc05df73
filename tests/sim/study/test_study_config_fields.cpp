// Every field of a prediction config is honoured or refused: each one edited in turn (to
// another valid value) changes the predicted T or its standard error, bit for bit, or is
// refused with an error naming it. A field read but ignored would give the very same T and
// standard error (the same seed, the same photons), which is how `predict --config` handed out
// default predictions before. The batches set the standard error; T moves with them only by the
// rounding of the batch totals (every photon has its own random stream), which can come out the
// same bits.
#include <functional>
#include <map>
#include <set>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tocd/core/error.hpp"
#include "tocd/sim/study/predictor.hpp"
#include "tocd/test/mc_request.hpp"

namespace st = tocd::sim::study;
using nlohmann::json;

namespace {

/// A cheap step: few photons, coarse tets (the paper preset's quality at 0.6 mm), deep enough
/// (1 mm into 2.5 mm) for a compressed region, whose optics are a field.
st::PredictionRequest base_request() {
  st::PredictionRequest r = tocd::test::mc_request(1.0, 2000, 1, 2);
  r.max_edge_mm = 0.6;
  return r;
}

}  // namespace

TEST(PredictionConfigFields, EachEditedFieldChangesTheResultOrIsRefused) {
  using Edit = std::function<void(json&)>;
  // One edit per field of the canonical config; the graded optics matter with the graded
  // model only, so that one edit switches the model on in its base too.
  const std::map<std::string, Edit> edits{
      {"displacement_mm", [](json& j) { j["displacement_mm"] = 1.25; }},
      {"thickness_mm", [](json& j) { j["thickness_mm"] = 2.0; }},
      {"material",
       [](json& j) { j["material"]["alpha"][0] = j["material"]["alpha"][0].get<double>() + 2.0; }},
      {"optics_model", [](json& j) { j["optics_model"] = "graded"; }},
      {"photons", [](json& j) { j["photons"] = 2400; }},
      {"seed", [](json& j) { j["seed"] = 2; }},
      {"mesh_preset", [](json& j) { j["mesh_preset"] = "paper"; }},
      {"baseline", [](json& j) { j["baseline"] = true; }},
      {"compressed_optics", [](json& j) { j["compressed_optics"]["mu_s"] = 10.0; }},
      {"graded",
       [](json& j) { j["graded"]["full_strain"] = j["graded"]["full_strain"].get<double>() * 0.5; }},
      {"batches", [](json& j) { j["batches"] = 10; }},
      {"max_edge_mm", [](json& j) { j["max_edge_mm"] = 0.7; }},
      {"tip_edge_mm", [](json& j) { j["tip_edge_mm"] = 0.1; }},
      {"pin_length_mm", [](json& j) { j["pin_length_mm"] = 3.0; }},
      {"pin_radius_mm", [](json& j) { j["pin_radius_mm"] = 1.4; }},
      {"slide_size_mm", [](json& j) { j["slide_size_mm"] = 12.0; }},
      {"slide_thickness_mm", [](json& j) { j["slide_thickness_mm"] = 0.9; }},
      {"fe_refinement", [](json& j) { j["fe_refinement"] = 1.5; }},
      // Written only when they differ from the default; edited in by name.
      {"fe_kinematics", [](json& j) { j["fe_kinematics"] = "plane-strain"; }},
      {"fe_bottom", [](json& j) { j["fe_bottom"] = "sliding"; }},
      {"compressed_log_strain", [](json& j) { j["compressed_log_strain"] = -0.3; }},
      {"fe_outer_radius_mm", [](json& j) { j["fe_outer_radius_mm"] = 5.0; }},
      {"slide_n", [](json& j) { j["slide_n"] = 1.6; }},
      // The FE goes through 0.5 mm on its way to the step: another path, other increments.
      {"fe_path_mm", [](json& j) { j["fe_path_mm"] = json::array({0.5}); }},
  };
  const json canonical = st::to_config(base_request());
  // Every field the config writes has an edit here (kind and version are refused when wrong,
  // tested at the command line).
  for (const auto& [key, value] : canonical.items()) {
    if (key == "kind" || key == "version") continue;
    EXPECT_TRUE(edits.count(key)) << "no edit for config field \"" << key << "\"";
  }
  st::Predictor predictor(1);
  const auto estimate_of = [&](const json& config) {
    const auto p = predictor.predict(st::request_from_config(config));
    return std::pair{p.T, p.T_stderr};
  };
  json graded_base = canonical;
  graded_base["optics_model"] = "graded";
  const auto base = estimate_of(canonical);
  const auto graded_estimate = estimate_of(graded_base);
  for (const auto& [key, edit] : edits) {
    const bool graded = key == "graded";
    json config = graded ? graded_base : canonical;
    edit(config);
    try {
      const auto estimate = estimate_of(config);
      EXPECT_NE(estimate, graded ? graded_estimate : base)
          << "\"" << key << "\" edited, T and its standard error unchanged: the field is ignored";
    } catch (const tocd::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << key << ": " << e.what();
    }
  }
}

// PredictionRequest <-> config JSON, and request validation.
#include <cmath>

#include <fmt/format.h>

#include "json_whole_number.hpp"
#include "material_json.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/geometry/composite.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace tocd::sim::study {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw tocd::ConfigError("prediction request: " + what);
}

}  // namespace

void validate(const PredictionRequest& r) {
  require(std::isfinite(r.thickness_mm) && r.thickness_mm > 0.0,
          fmt::format("thickness_mm must be > 0, got {}", r.thickness_mm));
  require(std::isfinite(r.displacement_mm) && r.displacement_mm >= 0.0,
          fmt::format("displacement_mm must be >= 0, got {}", r.displacement_mm));
  require(r.baseline || r.displacement_mm < r.thickness_mm,
          fmt::format("displacement_mm {} must be below the skin thickness {} mm", r.displacement_mm,
                      r.thickness_mm));
  require(r.optics_model == "threshold" || r.optics_model == "graded",
          fmt::format("optics_model must be 'threshold' or 'graded', got '{}'", r.optics_model));
  require(r.mesh_preset == "fast" || r.mesh_preset == "paper",
          fmt::format("mesh_preset must be 'fast' or 'paper', got '{}'", r.mesh_preset));
  require(r.photons > 0, "photons must be > 0");
  require(r.batches >= 2, fmt::format("batches must be >= 2, got {}", r.batches));
  require(r.threads >= 0, fmt::format("threads must be >= 0, got {}", r.threads));
  require(r.max_edge_mm >= 0.0, fmt::format("max_edge_mm must be >= 0, got {}", r.max_edge_mm));
  require(r.tip_edge_mm >= 0.0, fmt::format("tip_edge_mm must be >= 0, got {}", r.tip_edge_mm));
  require(r.pin_radius_mm > 0.0 && r.pin_length_mm > r.pin_radius_mm,
          fmt::format("pin: radius {} mm must be > 0 and below its length {} mm", r.pin_radius_mm,
                      r.pin_length_mm));
  require(r.slide_size_mm > 2.0 * r.pin_radius_mm && r.slide_thickness_mm > 0.0,
          fmt::format("slide {} x {} mm must be wider than the pin", r.slide_size_mm, r.slide_thickness_mm));
  require(r.fe_refinement > 0.0, fmt::format("fe_refinement must be > 0, got {}", r.fe_refinement));
  require(std::isfinite(r.compressed_log_strain) && r.compressed_log_strain < 0.0,
          fmt::format("compressed_log_strain must be < 0, got {}", r.compressed_log_strain));
  require(r.fe_outer_radius_mm == 0.0 || r.fe_outer_radius_mm > r.pin_radius_mm,
          fmt::format("fe_outer_radius_mm {} must be 0 (half the slide) or above the pin radius",
                      r.fe_outer_radius_mm));
  require(r.slide_n == 0.0 || (r.slide_n >= 1.0 && r.slide_n < 3.0),
          fmt::format("slide_n {} must be 0 (glass) or in [1, 3)", r.slide_n));
  mc::Optics one;
  one.regions[geometry::Region::compressed] = r.compressed_optics;
  mc::validate(one, "compressed_optics");
  (void)graded_optics(r.graded);
}

nlohmann::json to_config(const PredictionRequest& r) {
  validate(r);
  nlohmann::json j;
  j["kind"] = "tocdlab.prediction";
  j["version"] = 1;
  j["displacement_mm"] = r.displacement_mm;
  j["thickness_mm"] = r.thickness_mm;
  j["material"] = material_to_json(r.material);
  j["optics_model"] = r.optics_model;
  j["photons"] = r.photons;
  j["seed"] = r.seed;
  j["mesh_preset"] = r.mesh_preset;
  j["baseline"] = r.baseline;
  j["compressed_optics"] = to_json(r.compressed_optics);
  j["graded"] = to_json(r.graded);
  j["batches"] = r.batches;
  j["max_edge_mm"] = r.max_edge_mm;
  j["tip_edge_mm"] = r.tip_edge_mm;
  j["pin_length_mm"] = r.pin_length_mm;
  j["pin_radius_mm"] = r.pin_radius_mm;
  j["slide_size_mm"] = r.slide_size_mm;
  j["slide_thickness_mm"] = r.slide_thickness_mm;
  j["fe_refinement"] = r.fe_refinement;
  if (r.fe_kinematics != fe::Kinematics::axisymmetric) j["fe_kinematics"] = fe::to_string(r.fe_kinematics);
  if (r.fe_bottom != fe::Bottom::bonded) j["fe_bottom"] = fe::to_string(r.fe_bottom);
  if (r.compressed_log_strain != -0.5) j["compressed_log_strain"] = r.compressed_log_strain;
  if (r.fe_outer_radius_mm > 0) j["fe_outer_radius_mm"] = r.fe_outer_radius_mm;
  if (r.slide_n > 0) j["slide_n"] = r.slide_n;
  return j;
}

PredictionRequest request_from_config(const nlohmann::json& j) {
  if (!j.is_object()) throw tocd::ConfigError("prediction config: expected a JSON object");
  PredictionRequest r;
  try {
    auto num = [&](const char* key, double& v) {
      if (j.contains(key)) v = j.at(key).get<double>();
    };
    num("displacement_mm", r.displacement_mm);
    num("thickness_mm", r.thickness_mm);
    if (j.contains("material")) r.material = material_from_json(j.at("material"));
    if (j.contains("optics_model")) r.optics_model = j.at("optics_model").get<std::string>();
    // Ranges as on the command line (docs/security.md).
    if (j.contains("photons"))
      r.photons = json_whole_number(j.at("photons"), "prediction config: photons", 1, 1'000'000'000'000);
    if (j.contains("seed"))
      r.seed = json_whole_number(j.at("seed"), "prediction config: seed", 0, UINT64_MAX);
    if (j.contains("mesh_preset")) r.mesh_preset = j.at("mesh_preset").get<std::string>();
    if (j.contains("baseline")) r.baseline = j.at("baseline").get<bool>();
    if (j.contains("compressed_optics"))
      r.compressed_optics = region_optics_from_json(j.at("compressed_optics"));
    if (j.contains("graded")) r.graded = graded_from_json(j.at("graded"));
    if (j.contains("batches"))
      r.batches =
          static_cast<int>(json_whole_number(j.at("batches"), "prediction config: batches", 2, 1'000'000));
    num("max_edge_mm", r.max_edge_mm);
    num("tip_edge_mm", r.tip_edge_mm);
    num("pin_length_mm", r.pin_length_mm);
    num("pin_radius_mm", r.pin_radius_mm);
    num("slide_size_mm", r.slide_size_mm);
    num("slide_thickness_mm", r.slide_thickness_mm);
    num("fe_refinement", r.fe_refinement);
    if (j.contains("fe_kinematics"))
      r.fe_kinematics = fe::parse_kinematics(j.at("fe_kinematics").get<std::string>());
    if (j.contains("fe_bottom")) r.fe_bottom = fe::parse_bottom(j.at("fe_bottom").get<std::string>());
    num("compressed_log_strain", r.compressed_log_strain);
    num("fe_outer_radius_mm", r.fe_outer_radius_mm);
    num("slide_n", r.slide_n);
  } catch (const nlohmann::json::exception& e) {
    throw tocd::ConfigError(fmt::format("prediction config: {}", e.what()));
  }
  validate(r);
  return r;
}

ConfigDocument config_document_from_json(const nlohmann::json& document) {
  const nlohmann::json* j = &document;
  // `predict --json` output: the config is one level down.
  if (j->is_object() && j->contains("config") && j->at("config").is_object()) j = &j->at("config");
  ConfigDocument d;
  if (!j->is_object() || !j->contains("step")) {
    d.step = request_from_config(*j);
    return d;
  }
  // A run's stored prediction: T(step) / T(baseline), each with its own full config.
  if (!j->at("step").is_object())
    throw tocd::ConfigError("prediction config: \"step\" must be a prediction config object");
  d.step = request_from_config(j->at("step"));
  if (j->contains("baseline")) {
    if (!j->at("baseline").is_object())
      throw tocd::ConfigError(
          "prediction config: \"baseline\" beside \"step\" must be a prediction config object");
    d.baseline = request_from_config(j->at("baseline"));
  }
  if (j->contains("quantity")) {
    if (!j->at("quantity").is_string())
      throw tocd::ConfigError("prediction config: \"quantity\" must be a string");
    d.quantity = j->at("quantity").get<std::string>();
  }
  return d;
}

}  // namespace tocd::sim::study

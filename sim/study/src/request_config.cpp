// PredictionRequest <-> config JSON, and request validation.
#include <cmath>

#include <fmt/format.h>

#include "composite_spec.hpp"
#include "json_keys.hpp"
#include "json_whole_number.hpp"
#include "material_json.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/geometry/composite.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace tocd::sim::study {
namespace {

constexpr const char* kKind = "tocdlab.prediction";
constexpr int kVersion = 1;

void require(bool ok, const std::string& what) {
  if (!ok) throw tocd::ConfigError("prediction request: " + what);
}

// The request's plain numbers that every config holds, each under its field's name: to_config
// writes and request_from_config reads them from this one list.
struct NumberField {
  const char* key;
  double PredictionRequest::*value;
};
constexpr NumberField kNumberFields[] = {
    {"displacement_mm", &PredictionRequest::displacement_mm},
    {"thickness_mm", &PredictionRequest::thickness_mm},
    {"max_edge_mm", &PredictionRequest::max_edge_mm},
    {"tip_edge_mm", &PredictionRequest::tip_edge_mm},
    {"pin_length_mm", &PredictionRequest::pin_length_mm},
    {"pin_radius_mm", &PredictionRequest::pin_radius_mm},
    {"slide_size_mm", &PredictionRequest::slide_size_mm},
    {"slide_thickness_mm", &PredictionRequest::slide_thickness_mm},
    {"fe_refinement", &PredictionRequest::fe_refinement},
};

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
  require(
      r.photons >= static_cast<std::uint64_t>(r.batches),
      fmt::format("photons must be at least the {} Monte Carlo batches (each batch needs a photon), got {}",
                  r.batches, r.photons));
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
  for (std::size_t k = 0; k < r.fe_path_mm.size(); ++k) {
    const double d = r.fe_path_mm[k];
    require(std::isfinite(d) && d > 0.0 && d < r.displacement_mm && (k == 0 || d > r.fe_path_mm[k - 1]),
            fmt::format("fe_path_mm: {} mm (entry {}) must be above 0, above the entry before it and below "
                        "displacement_mm {}",
                        d, k + 1, r.displacement_mm));
  }
  require(r.fe_path_mm.empty() || !r.baseline, "fe_path_mm: the glass-only baseline has no FE");
  require(r.slide_n == 0.0 || (r.slide_n >= 1.0 && r.slide_n < 3.0),
          fmt::format("slide_n {} must be 0 (glass) or in [1, 3)", r.slide_n));
  // A mesh too fine to build is refused before the FE (TetGen would run for hours).
  geometry::SkinProfile flat;
  flat.thickness_mm = r.thickness_mm;
  try {
    geometry::check_mesh_size(composite_spec(r, flat));
  } catch (const geometry::GeometryError& e) {
    throw ConfigError(
        fmt::format("max_edge_mm {} / tip_edge_mm {}: {}", r.max_edge_mm, r.tip_edge_mm, e.what()));
  }
  mc::Optics one;
  one.regions[geometry::Region::compressed] = r.compressed_optics;
  mc::validate(one, "compressed_optics");
  (void)graded_optics(r.graded);
}

nlohmann::json to_config(const PredictionRequest& r) {
  validate(r);
  nlohmann::json j;
  j["kind"] = kKind;
  j["version"] = kVersion;
  for (const auto& f : kNumberFields) j[f.key] = r.*f.value;
  j["material"] = material_to_json(r.material);
  j["optics_model"] = r.optics_model;
  j["photons"] = r.photons;
  j["seed"] = r.seed;
  j["mesh_preset"] = r.mesh_preset;
  j["baseline"] = r.baseline;
  j["compressed_optics"] = to_json(r.compressed_optics);
  j["graded"] = to_json(r.graded);
  j["batches"] = r.batches;
  if (r.fe_kinematics != fe::Kinematics::axisymmetric) j["fe_kinematics"] = fe::to_string(r.fe_kinematics);
  if (r.fe_bottom != fe::Bottom::bonded) j["fe_bottom"] = fe::to_string(r.fe_bottom);
  if (r.compressed_log_strain != -0.5) j["compressed_log_strain"] = r.compressed_log_strain;
  if (r.fe_outer_radius_mm > 0) j["fe_outer_radius_mm"] = r.fe_outer_radius_mm;
  if (r.slide_n > 0) j["slide_n"] = r.slide_n;
  if (!r.fe_path_mm.empty()) j["fe_path_mm"] = r.fe_path_mm;
  return j;
}

mc::Optics optics_of(const PredictionRequest& r) {
  mc::Optics o = (!r.baseline && r.optics_model == "graded") ? graded_optics(r.graded)
                                                             : threshold_optics(r.compressed_optics);
  if (r.slide_n > 0) o.regions[geometry::Region::slide].n = r.slide_n;
  return o;
}

nlohmann::json optics_record(const PredictionRequest& r) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [id, o] : optics_of(r).regions) j[std::to_string(id)] = to_json(o);
  return j;
}

namespace {

// What a config may say about itself: this kind, this version (either may be left out of a
// hand-written request; config_document_from_json asks for the kind).
void check_kind_and_version(const nlohmann::json& j) {
  if (j.contains("kind") && j.at("kind") != kKind)
    throw tocd::ConfigError(
        fmt::format("prediction config: \"kind\" is {}, expected \"{}\"", j.at("kind").dump(), kKind));
  if (j.contains("version") && j.at("version") != kVersion)
    throw tocd::ConfigError(
        fmt::format("prediction config: \"version\" {} is not supported (this tocdlab reads version {})",
                    j.at("version").dump(), kVersion));
}

}  // namespace

PredictionRequest request_from_config(const nlohmann::json& j) {
  if (!j.is_object()) throw tocd::ConfigError("prediction config: expected a JSON object");
  require_known_keys(j,
                     {"kind",
                      "version",
                      "displacement_mm",
                      "thickness_mm",
                      "material",
                      "optics_model",
                      "photons",
                      "seed",
                      "mesh_preset",
                      "baseline",
                      "compressed_optics",
                      "graded",
                      "batches",
                      "max_edge_mm",
                      "tip_edge_mm",
                      "pin_length_mm",
                      "pin_radius_mm",
                      "slide_size_mm",
                      "slide_thickness_mm",
                      "fe_refinement",
                      "fe_kinematics",
                      "fe_bottom",
                      "compressed_log_strain",
                      "fe_outer_radius_mm",
                      "slide_n",
                      "fe_path_mm",
                      "optics"},
                     "prediction config");
  check_kind_and_version(j);
  PredictionRequest r;
  try {
    auto num = [&](const char* key, double& v) {
      if (j.contains(key)) v = j.at(key).get<double>();
    };
    for (const auto& f : kNumberFields) num(f.key, r.*f.value);
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
    if (j.contains("fe_kinematics"))
      r.fe_kinematics = fe::parse_kinematics(j.at("fe_kinematics").get<std::string>());
    if (j.contains("fe_bottom")) r.fe_bottom = fe::parse_bottom(j.at("fe_bottom").get<std::string>());
    num("compressed_log_strain", r.compressed_log_strain);
    num("fe_outer_radius_mm", r.fe_outer_radius_mm);
    num("slide_n", r.slide_n);
    if (j.contains("fe_path_mm")) r.fe_path_mm = j.at("fe_path_mm").get<std::vector<double>>();
  } catch (const nlohmann::json::exception& e) {
    throw tocd::ConfigError(fmt::format("prediction config: {}", e.what()));
  }
  validate(r);
  // "optics" records what every region got from the fields above; it is not an input. An
  // edited copy would be silently replaced, so it must match or the config is refused.
  if (j.contains("optics") && j.at("optics") != optics_record(r)) {
    std::string region = "?";
    const nlohmann::json want = optics_record(r);
    if (j.at("optics").is_object()) {
      for (const auto& [id, o] : j.at("optics").items())
        if (!want.contains(id) || want.at(id) != o) {
          region = id;
          break;
        }
    }
    throw tocd::ConfigError(fmt::format(
        "prediction config: \"optics\" (region {}) differs from the optics the config's fields give; it is "
        "the "
        "record of a prediction's optics, not an input: edit \"compressed_optics\" (threshold model) or "
        "\"graded\" instead, or remove \"optics\"",
        region));
  }
  return r;
}

ConfigDocument config_document_from_json(const nlohmann::json& document) {
  const nlohmann::json* j = &document;
  // `predict --json` output: the config is one level down.
  if (j->is_object() && j->contains("config") && j->at("config").is_object()) j = &j->at("config");
  ConfigDocument d;
  // A document is something tocdlab wrote: each config in it names its kind ("{}" or a
  // stray JSON file is refused, not read as the defaults).
  const auto require_kind = [](const nlohmann::json& c, const char* where) {
    if (c.is_object() && !c.contains("kind"))
      throw tocd::ConfigError(fmt::format(
          "prediction config{}: no \"kind\" key; a tocdlab prediction config has \"kind\": \"{}\" "
          "(write one with tocdlab predict --json)",
          where, kKind));
  };
  if (!j->is_object() || !j->contains("step")) {
    require_kind(*j, "");
    d.step = request_from_config(*j);
    return d;
  }
  require_known_keys(*j, {"quantity", "step", "baseline"}, "stored prediction config");
  // A run's stored prediction: T(step) / T(baseline), each with its own full config.
  if (!j->at("step").is_object())
    throw tocd::ConfigError("prediction config: \"step\" must be a prediction config object");
  require_kind(j->at("step"), " \"step\"");
  d.step = request_from_config(j->at("step"));
  if (j->contains("baseline")) {
    if (!j->at("baseline").is_object())
      throw tocd::ConfigError(
          "prediction config: \"baseline\" beside \"step\" must be a prediction config object");
    require_kind(j->at("baseline"), " \"baseline\"");
    d.baseline = request_from_config(j->at("baseline"));
  }
  if (j->contains("quantity")) {
    if (!j->at("quantity").is_string())
      throw tocd::ConfigError("prediction config: \"quantity\" must be a string");
    d.quantity = j->at("quantity").get<std::string>();
  }
  return d;
}

geometry::CompositeSpec composite_spec(const PredictionRequest& r, const geometry::SkinProfile& profile) {
  geometry::CompositeSpec s;
  s.slide_size_mm = r.slide_size_mm;
  s.skin_size_mm = r.slide_size_mm;
  s.slide_thickness_mm = r.slide_thickness_mm;
  s.pin_radius_mm = r.pin_radius_mm;
  s.pin_length_mm = r.pin_length_mm;
  s.pin_displacement_mm = r.baseline ? 0.0 : r.displacement_mm;
  s.baseline = r.baseline;
  s.skin = profile;
  s.size.preset = r.mesh_preset;
  s.size.max_edge_mm = r.max_edge_mm;
  s.size.tip_edge_mm = r.tip_edge_mm;
  return s;
}

}  // namespace tocd::sim::study

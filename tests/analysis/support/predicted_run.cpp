#include "predicted_run.hpp"

#include <memory>

#include <nlohmann/json.hpp>

#include "tocd/analysis/sim_step_predictor.hpp"
#include "tocd/db/database.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace tocd::analysis::testing {

std::int64_t write_predicted_run(const std::filesystem::path& path, const PredictedRunSpec& spec) {
  auto database = db::Database::open(path);
  db::NewRun nr;
  nr.name = "predicted run";
  const db::RunRecord run = database.create_run(nr);
  const auto load = database.add_channel({0, run.id, "load", "N", 0, 1000.0});
  SimPredictorSettings settings;
  settings.photons = spec.photons;
  SimStepPredictor predictor(std::make_shared<sim::study::Predictor>(1), settings);
  for (std::size_t k = 0; k < spec.displacements_mm.size(); ++k) {
    db::StepRecord s;
    s.run_id = run.id;
    s.index = static_cast<int>(k);
    s.target_displacement_mm = spec.displacements_mm[k];
    s.nominal_strain = s.target_displacement_mm / spec.thickness_mm;
    s.measured_transmission = 0.5;
    s.channels = {{load.id, 0.1 * static_cast<double>(k), 0.001, 100}};
    database.add_step(s);
    acquisition::RecordedStep step;
    step.run_id = run.id;
    step.index = s.index;
    step.displacement_mm = s.target_displacement_mm;
    step.thickness_mm = spec.thickness_mm;
    database.add_prediction(acquisition::prediction_record(run.id, s.index, predictor.predict(step).get()));
  }
  database.set_run_status(run.id, db::RunStatus::completed);
  return run.id;
}

std::string scaled_fit_json(double factor, const std::vector<double>& band_factors) {
  const auto published = sim::study::published_skin_material();
  auto law = [&](double c) {
    std::vector<double> mu, D;
    for (double m : published.mu) mu.push_back(c * m);
    for (double d : published.D) D.push_back(d / c);  // the bulk modulus scales with the shear moduli
    return nlohmann::json{{"mu_MPa", mu}, {"alpha", published.alpha}, {"D_per_MPa", D}};
  };
  nlohmann::json bands = nlohmann::json::array();
  for (std::size_t k = 0; k < band_factors.size(); ++k) {
    auto j = law(band_factors[k]);
    j["label"] = "band " + std::to_string(k + 1);
    bands.push_back(j);
  }
  return nlohmann::json{{"ogden", law(factor)}, {"confidence_laws", bands}}.dump();
}

}  // namespace tocd::analysis::testing

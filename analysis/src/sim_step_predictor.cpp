#include "tocd/analysis/sim_step_predictor.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tocd/core/error.hpp"
#include "tocd/sim/study/run_settings.hpp"

namespace tocd::analysis {

RelativeTransmission relative_to_baseline(double T, double T_se, double T0, double T0_se) {
  if (!(T0 > 0)) throw Error("baseline transmission of the glass-only simulation is not positive");
  RelativeTransmission r;
  r.T = T / T0;
  // First-order propagation for a ratio of independent estimates.
  const double rel_T = T > 0 ? T_se / T : 0.0;
  const double rel_0 = T0_se / T0;
  r.T_stderr = std::abs(r.T) * std::sqrt(rel_T * rel_T + rel_0 * rel_0);
  return r;
}

SimStepPredictor::SimStepPredictor(std::shared_ptr<sim::study::Predictor> predictor,
                                   SimPredictorSettings settings)
    : predictor_(std::move(predictor)), settings_(std::move(settings)) {
  if (!predictor_) throw ConfigError("SimStepPredictor needs a sim::study::Predictor");
  validate(settings_);
}

namespace {

/// The request `settings` make for a step of this geometry.
sim::study::PredictionRequest request_of(const SimPredictorSettings& settings, double displacement_mm,
                                         double thickness_mm) {
  sim::study::PredictionRequest r;
  r.displacement_mm = displacement_mm;
  r.thickness_mm = thickness_mm;
  r.material = settings.material;
  r.optics_model = settings.optics_model;
  sim::study::copy_run_settings(r, settings);
  return r;
}

}  // namespace

void validate(const SimPredictorSettings& settings) {
  // The glass-only baseline every step is predicted against: its request carries every
  // setting, and needs no sample geometry (the thickness is any valid one).
  sim::study::PredictionRequest r = request_of(settings, 0.0, 1.0);
  r.baseline = true;
  try {
    sim::study::validate(r);
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("predictions: {}", e.what()));
  }
}

sim::study::PredictionRequest SimStepPredictor::request_for(double displacement_mm,
                                                            double thickness_mm) const {
  sim::study::PredictionRequest r = request_of(settings_, displacement_mm, thickness_mm);
  r.cancel = cancel_;
  return r;
}

void SimStepPredictor::cancel() noexcept {
  cancel_->store(true);
}

std::shared_future<sim::study::Prediction> SimStepPredictor::baseline(double thickness_mm) {
  std::lock_guard lock(mutex_);
  if (!baseline_) {
    sim::study::PredictionRequest r = request_for(0.0, thickness_mm);
    r.baseline = true;
    // Its own random stream: the ratio's two estimates must be independent.
    r.seed = settings_.seed + 0x9E3779B97F4A7C15ULL;
    baseline_ = predictor_->submit(r).share();
  }
  return *baseline_;
}

void SimStepPredictor::prepare(double thickness_mm) {
  (void)baseline(thickness_mm);
}

std::vector<double> SimStepPredictor::path_before(const acquisition::RecordedStep& step) {
  std::lock_guard lock(mutex_);
  if (!(step.displacement_mm > 0)) return {};  // no contact, no FE
  // Another sample, or the pin went back: the FE starts again from first touch.
  if (step.thickness_mm != path_thickness_mm_ || (!path_.empty() && step.displacement_mm <= path_.back()))
    path_.clear();
  path_thickness_mm_ = step.thickness_mm;
  std::vector<double> before = path_;
  path_.push_back(step.displacement_mm);
  return before;
}

std::future<acquisition::PredictedStep> SimStepPredictor::predict(const acquisition::RecordedStep& step) {
  sim::study::PredictionRequest request = request_for(step.displacement_mm, step.thickness_mm);
  sim::study::validate(request);  // a bad step fails here, in the caller's thread
  request.fe_path_mm = path_before(step);
  auto base = baseline(step.thickness_mm);
  auto fut = predictor_->submit(request).share();
  return std::async(std::launch::async, [base, fut]() {
    const auto t0 = std::chrono::steady_clock::now();
    const sim::study::Prediction& b = base.get();
    const sim::study::Prediction& p = fut.get();
    const RelativeTransmission rel = relative_to_baseline(p.T, p.T_stderr, b.T, b.T_stderr);
    acquisition::PredictedStep out;
    out.T = rel.T;
    out.T_stderr = rel.T_stderr;
    nlohmann::json config;
    config["quantity"] = "T(step) / T(glass-only baseline)";
    config["step"] = p.config;
    config["baseline"] = b.config;
    out.config_json = config.dump();
    out.fe_seconds = p.fe_seconds;
    out.mesh_seconds = p.mesh_seconds;
    out.mc_seconds = p.mc_seconds;
    out.seconds = p.fe_seconds + p.mesh_seconds + p.mc_seconds +
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    nlohmann::json summary;
    summary["T_absolute"] = {{"mean", p.T}, {"se", p.T_stderr}};
    summary["T_baseline"] = {{"mean", b.T}, {"se", b.T_stderr}};
    summary["side_loss"] = p.side_loss;
    summary["tets"] = p.tets;
    summary["fe"] = p.fe_summary;
    summary["mesh"] = p.mesh_stats;
    out.summary_json = summary.dump();
    return out;
  });
}

std::shared_ptr<acquisition::StepPredictor> make_recording_predictor(SimPredictorSettings settings) {
  // One FE + MC prediction at a time: the recorded steps come one by one.
  if (settings.threads == 0)
    settings.threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()) - 1);
  return std::make_shared<SimStepPredictor>(std::make_shared<sim::study::Predictor>(1, nullptr, true),
                                            settings);
}

}  // namespace tocd::analysis

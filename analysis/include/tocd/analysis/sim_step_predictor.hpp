#pragma once

#include <atomic>
#include <cstdint>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "tocd/acquisition/step_predictor.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace tocd::analysis {

/// How recorded steps are simulated. Every field ends up in the stored prediction config.
struct SimPredictorSettings {
  std::uint64_t photons = 100000;
  std::uint64_t seed = 1;
  std::string mesh_preset = "fast";
  std::string optics_model = "threshold";  ///< "threshold" | "graded"
  int threads = 0;                         ///< Monte Carlo threads, 0 = all cores
  /// Model material; default: the published skin. The sample's thickness comes from the step.
  sim::material::OgdenParameters material = sim::study::published_skin_material();
};

/// Throws tocd::ConfigError naming the setting when no step could be predicted with these
/// settings (too few photons for the batches, an unknown mesh preset or optics model): called
/// before a run starts, so that a run never records steps it cannot predict.
void validate(const SimPredictorSettings& settings);

/// Predicts a recorded step with the FE + mesh + Monte Carlo chain of sim::study.
///
/// The measured transmission of a step is power / glass-only baseline power, so the predicted
/// value is the same ratio: T(step) / T(glass-only baseline geometry), both from the Monte
/// Carlo, with the standard error propagated from both (independent seeds). The baseline is
/// simulated once, from prepare() (the run's start) or else the first step, and shared by
/// every step.
///
/// A run's steps are one loading path while the pin only goes deeper: each step's FE goes on
/// from the previous step's (PredictionRequest::fe_path_mm, the displacements of the run's
/// earlier steps in contact since the pin last went back), so a deep step's FE costs the way
/// from the step before, not from first touch. Steps must come in the order they were
/// recorded, as the engine hands them over.
class SimStepPredictor : public acquisition::StepPredictor {
 public:
  SimStepPredictor(std::shared_ptr<sim::study::Predictor> predictor, SimPredictorSettings settings);
  void prepare(double thickness_mm) override;
  std::future<acquisition::PredictedStep> predict(const acquisition::RecordedStep& step) override;
  void cancel() noexcept override;

  /// The request the predictor runs for a step (exposed for tests and the stored config).
  sim::study::PredictionRequest request_for(double displacement_mm, double thickness_mm) const;

 private:
  std::shared_future<sim::study::Prediction> baseline(double thickness_mm);
  /// The loading path before `step` (its fe_path_mm), and `step` appended to the run's path.
  std::vector<double> path_before(const acquisition::RecordedStep& step);

  std::shared_ptr<sim::study::Predictor> predictor_;
  SimPredictorSettings settings_;
  std::shared_ptr<std::atomic<bool>> cancel_ = std::make_shared<std::atomic<bool>>(false);
  std::mutex mutex_;
  std::optional<std::shared_future<sim::study::Prediction>> baseline_;
  std::vector<double> path_;  ///< displacements of the run's steps on the current loading path
  double path_thickness_mm_ = 0;
};

/// The simulator's predictor of a recording's steps, as every front end hands it to the lab
/// session (acquisition::LabSessionOptions::predictor): its threads run at the background
/// niceness (10), so that predictions never cost the pollers a reading, and its Monte Carlo
/// leaves one core to them and the writer unless `settings` chose a thread count. Throws
/// ConfigError for settings no step could be predicted with.
std::shared_ptr<acquisition::StepPredictor> make_recording_predictor(SimPredictorSettings settings);

/// Transmission relative to the baseline with its propagated standard error.
struct RelativeTransmission {
  double T = 0, T_stderr = 0;
};
RelativeTransmission relative_to_baseline(double T, double T_se, double T0, double T0_se);

}  // namespace tocd::analysis

#pragma once

#include <cstdint>
#include <future>
#include <string>

#include "tocd/db/records.hpp"

namespace tocd::acquisition {

/// A step as recorded, handed to the simulator for a prediction of its transmission.
struct RecordedStep {
  std::int64_t run_id = 0;
  int index = 0;
  double displacement_mm = 0;  ///< target pin displacement into the sample
  double thickness_mm = 0;
  double load_N = 0;      ///< mean load over the recording window
  double measured_T = 0;  ///< mean power / baseline power
};

/// The simulator's answer for one step.
struct PredictedStep {
  double T = 0, T_stderr = 0;
  std::string config_json;  ///< everything needed to reproduce the prediction
  double seconds = 0;       ///< wall time of the prediction
  double fe_seconds = -1, mesh_seconds = -1, mc_seconds = -1;  ///< < 0 = not reported
  std::string summary_json;                                    ///< optional extras ("" = none)
  /// Real seconds from the run's prediction queue receiving the step to the prediction being
  /// stored (db::PredictionRecord::latency_s). The queue sets it, never a predictor: < 0 = not
  /// measured (a prediction made outside a run).
  double latency_s = -1;
};

/// The database record of `p` as the prediction of step `step_index` of run `run_id`: the
/// stage timings a predictor did not report, and a latency not measured, stay unset; the
/// software version is this build's.
db::PredictionRecord prediction_record(std::int64_t run_id, int step_index, const PredictedStep& p);

/// Predicts a recorded step's transmission. The simulator's implementation, over
/// sim::study::Predictor, is analysis::SimStepPredictor (analysis/src/sim_step_predictor.cpp):
/// acquisition knows the simulator only through this interface. The engine calls predict()
/// from its prediction thread, never from an acquisition thread, and waits on the futures
/// there; an exception stored in the future is logged as a "prediction" event and the step
/// keeps no prediction.
class StepPredictor {
 public:
  virtual ~StepPredictor() = default;
  /// A run of a sample `thickness_mm` thick starts recording steps: a predictor may begin what
  /// every step needs (the simulator's glass-only baseline), so that the first step's
  /// prediction does not wait for it. Called once per run, on the prediction thread, before
  /// the first predict().
  virtual void prepare(double thickness_mm) { (void)thickness_mm; }
  virtual std::future<PredictedStep> predict(const RecordedStep& step) = 0;
  /// Stops every prediction asked for so far, and every later one, as soon as it can (an
  /// operator's abort, a signal): their futures then hold a tocd::Cancelled. Called from any
  /// thread. A predictor that cannot stop early ignores it (its futures still land).
  virtual void cancel() noexcept {}
};

}  // namespace tocd::acquisition

#pragma once

// The prediction queue: recorded steps wait here for the StepPredictor, and its answers are
// stored next to the steps. Its worker runs on its own thread, so a slow simulator never holds
// up acquisition. It owns its queue, its lock and its thread.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "tocd/acquisition/step_predictor.hpp"
#include "tocd/db/database.hpp"

namespace tocd::acquisition {

class PredictionQueue {
 public:
  /// `event(message, step)` records a "prediction" event; `landed(step, prediction)` tells the
  /// observer. Both are called on the worker thread.
  using Event = std::function<void(const std::string& message, int step)>;
  using Landed = std::function<void(int step, const PredictedStep& prediction)>;

  PredictionQueue(db::Database& db, std::shared_ptr<StepPredictor> predictor, Event event, Landed landed);
  /// Closes the queue and joins the worker (every prediction already asked for lands first).
  ~PredictionQueue();
  PredictionQueue(const PredictionQueue&) = delete;
  PredictionQueue& operator=(const PredictionQueue&) = delete;

  /// Whether there is a predictor (otherwise push() drops the step).
  bool enabled() const noexcept { return predictor_ != nullptr; }

  /// Starts the worker for run `run_id` of a sample `thickness_mm` thick (it tells the
  /// predictor first: StepPredictor::prepare); `done` is called on it once the queue was closed
  /// and every prediction has landed (also when the worker failed).
  void start(std::int64_t run_id, double thickness_mm, std::function<void()> done);
  void push(const RecordedStep& step);
  /// No more steps come; the worker ends when the pending ones have landed.
  void close();
  /// The pending predictions stop as soon as the predictor can stop them
  /// (StepPredictor::cancel), and steps pushed from now on are not predicted: each that does
  /// not land gets a "prediction" event naming `reason`. The worker still ends at close().
  void cancel(const std::string& reason);

  /// How the predictions of the run went so far (any thread).
  struct Counts {
    int asked = 0, stored = 0, failed = 0, cancelled = 0;
  };
  Counts counts() const;

 private:
  /// A step as the queue received it, and when (the start of its prediction's latency).
  struct ReceivedStep {
    RecordedStep step;
    std::chrono::steady_clock::time_point received;
  };

  void run();
  /// Stores `p` as the prediction of `r`; returns it with its latency.
  PredictedStep store(const ReceivedStep& r, PredictedStep p);
  /// The event and the count of a step whose prediction did not land.
  void not_landed(const RecordedStep& step, const std::string& why, bool cancelled);

  db::Database& db_;
  std::shared_ptr<StepPredictor> predictor_;
  Event event_;
  Landed landed_;
  std::int64_t run_id_ = 0;

  // Invariant: `closed_` and `cancelled_` only go from false to true; steps pushed after
  // closing are dropped, steps pushed after cancelling are reported not predicted.
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<ReceivedStep> queue_;
  bool closed_ = false;
  bool cancelled_ = false;
  std::string cancel_reason_;
  Counts counts_;

  std::thread worker_;
};

}  // namespace tocd::acquisition

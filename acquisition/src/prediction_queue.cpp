#include "prediction_queue.hpp"

#include <chrono>
#include <future>
#include <utility>

#include <fmt/format.h>

#include "tocd/core/error.hpp"
#include "tocd/core/log.hpp"
#include "tocd/core/version.hpp"

namespace tocd::acquisition {

PredictionQueue::PredictionQueue(db::Database& db, std::shared_ptr<StepPredictor> predictor, Event event,
                                 Landed landed)
    : db_(db), predictor_(std::move(predictor)), event_(std::move(event)), landed_(std::move(landed)) {}

PredictionQueue::~PredictionQueue() {
  close();
  if (worker_.joinable()) worker_.join();
}

void PredictionQueue::start(std::int64_t run_id, double thickness_mm, std::function<void()> done) {
  run_id_ = run_id;
  worker_ = std::thread([this, thickness_mm, done = std::move(done)] {
    try {
      // A predictor that cannot prepare still predicts: each step then says what failed.
      if (predictor_) predictor_->prepare(thickness_mm);
    } catch (const std::exception& e) {
      logger("acquisition")->warn("run {}: the predictor could not prepare: {}", run_id_, e.what());
    }
    try {
      run();
    } catch (const std::exception& e) {
      logger("acquisition")->error("run {}: prediction worker failed: {}", run_id_, e.what());
    } catch (...) {
      logger("acquisition")->error("run {}: prediction worker failed", run_id_);
    }
    // Had the worker failed, whoever waits for the run must still hear that it ended.
    {
      std::unique_lock lock(mu_);
      cv_.wait(lock, [&] { return closed_; });
    }
    done();
  });
}

void PredictionQueue::push(const RecordedStep& step) {
  if (!predictor_) return;
  const auto received = std::chrono::steady_clock::now();
  {
    std::lock_guard lock(mu_);
    if (closed_) return;
    queue_.push_back({step, received});
    ++counts_.asked;
  }
  cv_.notify_all();
}

void PredictionQueue::close() {
  {
    std::lock_guard lock(mu_);
    closed_ = true;
  }
  cv_.notify_all();
}

void PredictionQueue::cancel(const std::string& reason) {
  {
    std::lock_guard lock(mu_);
    if (cancelled_) return;
    cancelled_ = true;
    cancel_reason_ = reason;
  }
  if (predictor_) predictor_->cancel();
  cv_.notify_all();
}

PredictionQueue::Counts PredictionQueue::counts() const {
  std::lock_guard lock(mu_);
  return counts_;
}

void PredictionQueue::not_landed(const RecordedStep& step, const std::string& why, bool cancelled) {
  {
    std::lock_guard lock(mu_);
    ++(cancelled ? counts_.cancelled : counts_.failed);
  }
  event_(fmt::format("step {}: {}", step.index + 1, why), step.index);
}

void PredictionQueue::run() {
  std::deque<std::pair<ReceivedStep, std::future<PredictedStep>>> pending;
  for (;;) {
    std::deque<ReceivedStep> fresh;
    std::string cancelled;
    {
      std::unique_lock lock(mu_);
      if (pending.empty()) cv_.wait(lock, [&] { return closed_ || !queue_.empty(); });
      fresh.swap(queue_);
      if (cancelled_) cancelled = cancel_reason_;
      if (fresh.empty() && pending.empty() && closed_) return;
    }
    for (const auto& r : fresh) {
      if (!cancelled.empty()) {
        not_landed(r.step, "not predicted: " + cancelled, true);
        continue;
      }
      try {
        pending.emplace_back(r, predictor_->predict(r.step));
      } catch (const std::exception& e) {
        not_landed(r.step, fmt::format("prediction could not start: {}", e.what()), false);
      }
    }
    if (pending.empty()) continue;
    auto& [received, future] = pending.front();
    const RecordedStep& step = received.step;
    if (future.wait_for(std::chrono::milliseconds(20)) != std::future_status::ready) continue;
    try {
      const PredictedStep p = store(received, future.get());
      {
        std::lock_guard lock(mu_);
        ++counts_.stored;
      }
      event_(fmt::format("step {}: predicted T = {:.5f} +- {:.5f} (measured {:.5f}), {:.1f} s, "
                         "stored {:.1f} s after the step was recorded",
                         step.index + 1, p.T, p.T_stderr, step.measured_T, p.seconds, p.latency_s),
             step.index);
      landed_(step.index, p);
    } catch (const Cancelled& e) {
      std::string reason;
      {
        std::lock_guard lock(mu_);
        reason = cancel_reason_;
      }
      not_landed(step, fmt::format("not predicted: {} ({})", reason.empty() ? "cancelled" : reason, e.what()),
                 true);
    } catch (const std::exception& e) {
      not_landed(step, fmt::format("prediction failed: {}", e.what()), false);
    }
    pending.pop_front();
  }
}

PredictedStep PredictionQueue::store(const ReceivedStep& r, PredictedStep p) {
  // Taken as the record goes to the database: the insert itself (milliseconds) is left out.
  p.latency_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - r.received).count();
  db_.add_prediction(prediction_record(run_id_, r.step.index, p));
  return p;
}

db::PredictionRecord prediction_record(std::int64_t run_id, int step_index, const PredictedStep& p) {
  db::PredictionRecord rec;
  rec.run_id = run_id;
  rec.step_index = step_index;
  rec.config_json = p.config_json;
  rec.T = p.T;
  rec.T_stderr = p.T_stderr;
  if (p.fe_seconds >= 0) rec.fe_seconds = p.fe_seconds;
  if (p.mesh_seconds >= 0) rec.mesh_seconds = p.mesh_seconds;
  if (p.mc_seconds >= 0) rec.mc_seconds = p.mc_seconds;
  if (p.latency_s >= 0) rec.latency_s = p.latency_s;
  rec.total_seconds = p.seconds;
  rec.software_version = std::string(version());
  rec.summary_json = p.summary_json;
  return rec;
}

}  // namespace tocd::acquisition

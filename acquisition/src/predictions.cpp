// The prediction worker: hands recorded steps to the StepPredictor and stores the answers
// next to the steps. It runs on its own thread so a slow simulator never holds up acquisition.
#include <fmt/format.h>

#include "engine_impl.hpp"
#include "tocd/core/version.hpp"

namespace tocd::acquisition {

void Engine::Impl::queue_prediction(const RecordedStep& step) {
  {
    std::lock_guard lock(pred_mu);
    pred_queue.push_back(step);
  }
  pred_cv.notify_all();
}

void Engine::Impl::run_predictions() {
  std::deque<std::pair<RecordedStep, std::future<PredictedStep>>> pending;
  for (;;) {
    std::deque<RecordedStep> fresh;
    {
      std::unique_lock lock(pred_mu);
      if (pending.empty()) pred_cv.wait(lock, [&] { return pred_stop || !pred_queue.empty(); });
      fresh.swap(pred_queue);
      if (fresh.empty() && pending.empty() && pred_stop) break;
    }
    for (const auto& step : fresh) {
      try {
        pending.emplace_back(step, predictor->predict(step));
      } catch (const std::exception& e) {
        emit_event("prediction",
                   fmt::format("step {}: prediction could not start: {}", step.index + 1, e.what()),
                   step.index);
      }
    }
    if (pending.empty()) continue;
    auto& [step, future] = pending.front();
    if (future.wait_for(std::chrono::milliseconds(20)) != std::future_status::ready) continue;
    try {
      const PredictedStep p = future.get();
      db::PredictionRecord rec;
      rec.run_id = run_id;
      rec.step_index = step.index;
      rec.config_json = p.config_json;
      rec.T = p.T;
      rec.T_stderr = p.T_stderr;
      if (p.fe_seconds >= 0) rec.fe_seconds = p.fe_seconds;
      if (p.mesh_seconds >= 0) rec.mesh_seconds = p.mesh_seconds;
      if (p.mc_seconds >= 0) rec.mc_seconds = p.mc_seconds;
      rec.total_seconds = p.seconds;
      rec.software_version = std::string(version());
      rec.summary_json = p.summary_json;
      db.add_prediction(rec);
      emit_event("prediction",
                 fmt::format("step {}: predicted T = {:.5f} +- {:.5f} (measured {:.5f}), {:.1f} s",
                             step.index + 1, p.T, p.T_stderr, step.measured_T, p.seconds),
                 step.index);
      // `index = step.index`: clang 14 cannot capture a structured binding.
      notify([&, index = step.index](EngineObserver& o) { o.on_prediction(index, p); });
    } catch (const std::exception& e) {
      emit_event("prediction", fmt::format("step {}: prediction failed: {}", step.index + 1, e.what()),
                 step.index);
    }
    pending.pop_front();
  }
  {
    std::lock_guard lock(mu);
    finished = true;
  }
  cv.notify_all();
}

}  // namespace tocd::acquisition

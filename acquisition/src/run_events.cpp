#include "run_events.hpp"

#include "tocd/core/log.hpp"

namespace tocd::acquisition {

void RunEvents::emit(const std::string& kind, const std::string& message, int step,
                     const std::string& data_json) {
  db::EventRecord e{0, run_id_, clock_.now_ns(), kind, message, step, data_json};
  logger("acquisition")->info("run {}: {}: {}", run_id_, kind, message);
  if (storage_failed_ || !recorder_.enqueue_event(e)) {
    try {
      db_.add_event(e);
    } catch (const std::exception& ex) {  // storage trouble is reported by the writer; never throw here
      logger("acquisition")
          ->error("run {}: event not stored ({}): {}: {}", run_id_, ex.what(), kind, message);
    }
  }
  notify([&](EngineObserver& o) { o.on_event(e); });
}

void RunEvents::observer_failed(const char* what) noexcept {
  try {
    logger("acquisition")->error("run {}: an observer callback threw: {}", run_id_, what);
  } catch (...) {  // logging itself failed: nothing more to do
  }
}

}  // namespace tocd::acquisition

#pragma once

// A stop request that wakes every thread sleeping on it, so that no wait of a poller outlasts
// a stop (a plain sleep for a whole poll period would).

#include <chrono>
#include <condition_variable>
#include <mutex>

namespace tocd::acquisition {

class StopSignal {
 public:
  void request() {
    {
      std::lock_guard lock(mu_);
      stop_ = true;
    }
    cv_.notify_all();
  }
  bool requested() const {
    std::lock_guard lock(mu_);
    return stop_;
  }
  /// Sleeps for `d` (real time) or until a stop is requested; true when stopped.
  bool sleep_for(std::chrono::nanoseconds d) const {
    std::unique_lock lock(mu_);
    return cv_.wait_for(lock, d, [&] { return stop_; });
  }

 private:
  mutable std::mutex mu_;
  mutable std::condition_variable cv_;
  bool stop_ = false;
};

}  // namespace tocd::acquisition

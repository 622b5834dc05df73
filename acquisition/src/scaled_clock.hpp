#pragma once

#include <chrono>
#include <cstdint>
#include <thread>

#include "tocd/core/clock.hpp"

namespace tocd::acquisition {

/// The engine's time: monotonic nanoseconds that start at `start_ns` and run `factor` times
/// faster than real time (factor 1 with start_ns = monotonic_ns() is the monotonic clock).
class ScaledClock {
 public:
  ScaledClock(double factor = 1.0, std::int64_t start_ns = monotonic_ns())
      : factor_(factor), start_ns_(start_ns), real_start_ns_(monotonic_ns()) {}

  std::int64_t now_ns() const noexcept {
    return start_ns_ +
           static_cast<std::int64_t>(static_cast<double>(monotonic_ns() - real_start_ns_) * factor_);
  }
  double factor() const noexcept { return factor_; }
  /// Real duration of `sim_s` simulated seconds.
  std::chrono::nanoseconds real(double sim_s) const noexcept {
    return std::chrono::nanoseconds(static_cast<std::int64_t>(sim_s / factor_ * 1e9));
  }
  /// Sleeps until simulated time `t_ns` (returns at once when it has passed).
  void sleep_until(std::int64_t t_ns) const {
    const std::int64_t ahead = t_ns - now_ns();
    if (ahead > 0) std::this_thread::sleep_for(real(static_cast<double>(ahead) * 1e-9));
  }

 private:
  double factor_;
  std::int64_t start_ns_;
  std::int64_t real_start_ns_;
};

}  // namespace tocd::acquisition

#pragma once

#include <atomic>
#include <cstdint>

namespace tocd::mocks {

/// The simulated instruments' sense of time: real monotonic time scaled by a factor, so a
/// ten-minute protocol can run in seconds in a test. Thread-safe.
class SimClock {
 public:
  /// `factor` simulated seconds pass per real second; must be > 0.
  explicit SimClock(double factor = 1.0);

  /// Simulated nanoseconds since the clock was made.
  std::int64_t now_ns() const noexcept;

  double factor() const noexcept { return factor_; }

 private:
  double factor_;
  std::int64_t start_ns_;
};

}  // namespace tocd::mocks

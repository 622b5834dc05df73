#pragma once

// Whether an instrument's interlock watches its readings, with one writer: the sequencer arms
// it (with a setpoint where the interlock needs one) and disarms it. The poller that checks
// the readings never writes it: it remembers which arming it has already acted on, so an
// interlock fires once per arming.

#include <cstdint>
#include <mutex>
#include <optional>

namespace tocd::acquisition {

class InterlockArming {
 public:
  /// What the poller sees: which arming (1, 2, ...) and its setpoint.
  struct Armed {
    std::uint64_t arming = 0;
    double setpoint = 0;
  };

  explicit InterlockArming(bool armed) {
    if (armed) arming_ = 1;
  }
  /// Sequencer only.
  void arm(double setpoint = 0) {
    std::lock_guard lock(mu_);
    ++count_;
    arming_ = count_;
    setpoint_ = setpoint;
  }
  /// Sequencer only.
  void disarm() {
    std::lock_guard lock(mu_);
    arming_ = 0;
  }
  /// The current arming; empty when disarmed.
  std::optional<Armed> armed() const {
    std::lock_guard lock(mu_);
    if (arming_ == 0) return std::nullopt;
    return Armed{arming_, setpoint_};
  }

 private:
  mutable std::mutex mu_;
  std::uint64_t count_ = 1;   // armings so far (the first may be at construction)
  std::uint64_t arming_ = 0;  // 0: disarmed
  double setpoint_ = 0;
};

}  // namespace tocd::acquisition

#include "tocd/mocks/sim_clock.hpp"

#include <cmath>
#include <string>

#include "tocd/core/clock.hpp"
#include "tocd/core/error.hpp"

namespace tocd::mocks {

SimClock::SimClock(double factor) : factor_(factor), start_ns_(monotonic_ns()) {
  if (!(factor > 0.0) || !std::isfinite(factor)) {
    throw ConfigError("simulated clock factor must be a positive number, got " + std::to_string(factor));
  }
}

std::int64_t SimClock::now_ns() const noexcept {
  return static_cast<std::int64_t>(static_cast<double>(monotonic_ns() - start_ns_) * factor_);
}

}  // namespace tocd::mocks

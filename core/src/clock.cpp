#include "tocd/core/clock.hpp"

#include <chrono>
#include <ctime>

#include <fmt/format.h>

namespace tocd {

std::int64_t monotonic_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::int64_t wall_clock_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string format_utc(std::int64_t epoch_ns) {
  std::int64_t seconds = epoch_ns / 1'000'000'000;
  std::int64_t rem_ns = epoch_ns % 1'000'000'000;
  if (rem_ns < 0) {  // floor division for times before 1970
    rem_ns += 1'000'000'000;
    --seconds;
  }
  const std::time_t t = static_cast<std::time_t>(seconds);
  std::tm utc{};
  gmtime_r(&t, &utc);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", utc.tm_year + 1900, utc.tm_mon + 1,
                     utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec, rem_ns / 1'000'000);
}

}  // namespace tocd

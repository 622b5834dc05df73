#pragma once

#include <cstdint>
#include <string>

namespace tocd {

/// Monotonic nanoseconds (CLOCK_MONOTONIC): orders samples, immune to wall-clock changes.
std::int64_t monotonic_ns() noexcept;

/// Wall-clock time as nanoseconds since the Unix epoch (UTC): the anchor stored with a run.
std::int64_t wall_clock_ns() noexcept;

/// ISO-8601 UTC text of an epoch-ns time, e.g. "2026-11-24T02:33:55.123Z".
std::string format_utc(std::int64_t epoch_ns);

}  // namespace tocd

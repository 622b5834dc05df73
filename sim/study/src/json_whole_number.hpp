// Whole numbers read from a JSON config. nlohmann's get<std::uint64_t>() turns -1 into
// 2^64 - 1 (a config could ask for 1.8e19 photons and run for ever), and get<int>() of 1e300 or
// of 18446744073709551616 (read as a double) is undefined behaviour (found by the
// predict_config fuzz target).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tocd/core/error.hpp"

namespace tocd::sim::study {

/// `value` as a whole number in [lo, hi]; a float is taken when it is integral and exact
/// (below 2^53). Throws ConfigError naming `what` and the accepted range otherwise.
inline std::uint64_t json_whole_number(const nlohmann::json& value, const std::string& what, std::uint64_t lo,
                                       std::uint64_t hi) {
  bool whole = false;
  std::uint64_t n = 0;
  if (value.is_number_unsigned()) {
    n = value.get<std::uint64_t>();
    whole = true;
  } else if (value.is_number_integer()) {  // signed: what a json built from an int holds
    const auto i = value.get<std::int64_t>();
    whole = i >= 0;
    if (whole) n = static_cast<std::uint64_t>(i);
  } else if (value.is_number_float()) {
    const double d = value.get<double>();
    whole = d >= 0.0 && d <= 9007199254740992.0 && d == std::floor(d);
    if (whole) n = static_cast<std::uint64_t>(d);
  }
  if (!whole || n < lo || n > hi)
    throw tocd::ConfigError(
        fmt::format("{} must be a whole number from {} to {}, got {}", what, lo, hi, value.dump()));
  return n;
}

}  // namespace tocd::sim::study

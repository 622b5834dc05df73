#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include <CLI/CLI.hpp>

namespace tocd::cli {

/// Most Monte Carlo photons any command accepts: 1e12 is days of CPU time on a workstation;
/// beyond it a typo (an extra zero, a negative number wrapped to 2^64) is more likely.
inline constexpr std::uint64_t kMaxPhotons = 1'000'000'000'000ULL;
/// Most threads any command accepts (0 means "all cores" where a command says so).
inline constexpr int kMaxThreads = 1024;

/// Check for a whole-number option: decimal digits only (no octal "010", hex "0x10" or
/// exponent), between lo and hi inclusive. The error states the value and the range, e.g.
/// "--photons: -5 is out of range: accepted 1 to 1000000000000".
CLI::Validator whole_in(std::int64_t lo, std::int64_t hi);
CLI::Validator whole_in(std::uint64_t lo, std::uint64_t hi);

/// Check for a real-number option: finite, between lo and hi inclusive.
CLI::Validator real_in(double lo, double hi);

/// Same as real_in but the lower end is excluded ("above 0 up to 100"): for sizes and
/// factors where zero is meaningless.
CLI::Validator real_above(double lo, double hi);

/// An option whose value must pass `range` (whole_in, real_in, real_above) and whose default
/// the help shows.
template <class T>
CLI::Option* add_ranged_option(CLI::App* cmd, const std::string& name, T& value, const std::string& help,
                               const CLI::Validator& range) {
  return cmd->add_option(name, value, help)->check(range)->capture_default_str();
}

/// The options every Monte Carlo command shares, with their ranges checked and their defaults
/// shown: a photon count (1 to kMaxPhotons; `name` is --photons or a more specific one), the
/// random seed (any 64-bit number) and the threads (0 = all cores, up to kMaxThreads).
CLI::Option* add_photons_option(CLI::App& cmd, const std::string& name, std::uint64_t& photons,
                                const std::string& help);
CLI::Option* add_seed_option(CLI::App& cmd, std::uint64_t& seed, const std::string& help);
CLI::Option* add_threads_option(CLI::App& cmd, int& threads, const std::string& help);

/// Applied once, after every command declared its options: each option typed as an unsigned
/// integer refuses negatives and anything but decimal digits (CLI11 would wrap "-5" to
/// 1.8e19 and read "010" as octal), each signed one anything but a decimal integer, and each
/// real-valued one NaN and infinities. Explicit ranges (whole_in, real_in) come on top.
void check_numeric_syntax(CLI::App& app);

}  // namespace tocd::cli

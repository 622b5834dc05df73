// Range and syntax checks for numeric command-line options, shared by every command.
#include "numeric_options.hpp"

#include <charconv>
#include <cmath>
#include <string>
#include <system_error>

#include <fmt/format.h>

namespace tocd::cli {
namespace {

constexpr const char* kRangeName = "tocd_range";  // name of every explicit range validator

// Decimal integer text: an optional sign and at least one digit, nothing else.
bool is_decimal_integer(const std::string& s) {
  std::size_t i = (!s.empty() && (s[0] == '-' || s[0] == '+')) ? 1 : 0;
  if (i == s.size()) return false;
  for (; i < s.size(); ++i)
    if (s[i] < '0' || s[i] > '9') return false;
  return true;
}

template <class Int>
std::string check_whole(const std::string& text, Int lo, Int hi) {
  if (!is_decimal_integer(text)) return fmt::format("'{}' is not a whole number (decimal digits only)", text);
  const char* first = text.c_str() + (text[0] == '+' ? 1 : 0);
  const char* last = text.c_str() + text.size();
  Int v{};
  const auto [end, ec] = std::from_chars(first, last, v);
  // A negative number for an unsigned option, or a number beyond the type, fails to parse:
  // report it against the range rather than as a syntax error.
  if (ec != std::errc{} || end != last || v < lo || v > hi)
    return fmt::format("{} is out of range: accepted {} to {}", text, lo, hi);
  return {};
}

std::string check_real(const std::string& text, double lo, double hi, bool open_below) {
  const char* first = text.c_str() + (!text.empty() && text[0] == '+' ? 1 : 0);
  const char* last = text.c_str() + text.size();
  double v = 0.0;
  const auto [end, ec] = std::from_chars(first, last, v);
  if (text.empty() || end != last || (ec != std::errc{} && ec != std::errc::result_out_of_range))
    return fmt::format("'{}' is not a number", text);
  const bool below = open_below ? !(v > lo) : !(v >= lo);
  if (ec == std::errc::result_out_of_range || !std::isfinite(v) || below || !(v <= hi)) {
    return fmt::format("{} is out of range: accepted {} {} up to {}", text, open_below ? "above" : "from", lo,
                       hi);
  }
  return {};
}

}  // namespace

CLI::Validator whole_in(std::int64_t lo, std::int64_t hi) {
  return CLI::Validator([lo, hi](std::string& s) { return check_whole(s, lo, hi); },
                        fmt::format("{} to {}", lo, hi), kRangeName);
}

CLI::Validator whole_in(std::uint64_t lo, std::uint64_t hi) {
  return CLI::Validator([lo, hi](std::string& s) { return check_whole(s, lo, hi); },
                        fmt::format("{} to {}", lo, hi), kRangeName);
}

CLI::Validator real_in(double lo, double hi) {
  return CLI::Validator([lo, hi](std::string& s) { return check_real(s, lo, hi, false); },
                        fmt::format("{} to {}", lo, hi), kRangeName);
}

CLI::Validator real_above(double lo, double hi) {
  return CLI::Validator([lo, hi](std::string& s) { return check_real(s, lo, hi, true); },
                        fmt::format("above {} up to {}", lo, hi), kRangeName);
}

namespace {

bool has_explicit_range(CLI::Option* opt) {
  try {
    opt->get_validator(kRangeName);
    return true;
  } catch (const CLI::OptionNotFound&) {
    return false;
  }
}

// Rewrites a decimal whole number to plain digits, so that CLI11's conversion (strtoull with
// base 0) cannot read "010" as octal. CLI11 runs transforms before checks; text that is not a
// whole number of the type is left alone for the explicit range to refuse with its own
// limits, or refused here with the type's limits when the option has no explicit range.
template <class Int>
CLI::Validator canonical_whole(bool refuse) {
  return CLI::Validator(
      [refuse](std::string& s) {
        std::string why = check_whole(s, std::numeric_limits<Int>::min(), std::numeric_limits<Int>::max());
        if (!why.empty()) return refuse ? why : std::string{};
        Int v{};
        std::from_chars(s.c_str() + (s[0] == '+' ? 1 : 0), s.c_str() + s.size(), v);
        s = fmt::format("{}", v);
        return std::string{};
      },
      "");
}

}  // namespace

void check_numeric_syntax(CLI::App& app) {
  for (CLI::Option* opt : app.get_options()) {
    const std::string type = opt->get_type_name();
    const std::string base = type.substr(0, type.find(':'));
    const bool ranged = has_explicit_range(opt);
    // Descriptions are left empty so that --help shows only the explicit ranges.
    if (base == "UINT") {
      opt->transform(canonical_whole<std::uint64_t>(!ranged));
    } else if (base == "INT") {
      opt->transform(canonical_whole<std::int64_t>(!ranged));
    } else if (base == "FLOAT" && !ranged) {
      opt->check(CLI::Validator(
          [](std::string& s) {
            return check_real(s, -std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                              false);
          },
          ""));
    }
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) check_numeric_syntax(*sub);
}

CLI::Option* add_photons_option(CLI::App& cmd, const std::string& name, std::uint64_t& photons,
                                const std::string& help) {
  return cmd.add_option(name, photons, help)
      ->check(whole_in(std::uint64_t{1}, kMaxPhotons))
      ->capture_default_str();
}

CLI::Option* add_seed_option(CLI::App& cmd, std::uint64_t& seed, const std::string& help) {
  return cmd.add_option("--seed", seed, help)
      ->check(whole_in(std::uint64_t{0}, std::numeric_limits<std::uint64_t>::max()))
      ->capture_default_str();
}

CLI::Option* add_threads_option(CLI::App& cmd, int& threads, const std::string& help) {
  return cmd.add_option("--threads", threads, help)
      ->check(whole_in(std::int64_t{0}, std::int64_t{kMaxThreads}))
      ->capture_default_str();
}

}  // namespace tocd::cli

// Strict parsing of SCPI numeric and error-queue answers: anything a lab user would not call
// "a number" is a protocol error that quotes the answer.
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "tocd/devices/scpi_client.hpp"

namespace tocd::devices {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r' || s.back() == '\n'))
    s.remove_suffix(1);
  return s;
}

/// Quotes an answer for an error message, escaping bytes that are not printable.
std::string quoted(std::string_view s) {
  std::string out = "\"";
  for (unsigned char c : s.substr(0, 80)) {
    if (c >= 0x20 && c < 0x7F && c != '"')
      out += static_cast<char>(c);
    else
      out += fmt::format("\\x{:02X}", c);
  }
  if (s.size() > 80) out += "...";
  return out + "\"";
}

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

/// SCPI <NRf>: [sign] digits [. digits] [E [sign] digits], at least one mantissa digit.
bool is_nrf(std::string_view s) {
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t digits = 0;
  while (i < s.size() && is_digit(s[i])) ++i, ++digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && is_digit(s[i])) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < s.size() && (s[i] == 'E' || s[i] == 'e')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    std::size_t exp_digits = 0;
    while (i < s.size() && is_digit(s[i])) ++i, ++exp_digits;
    if (exp_digits == 0) return false;
  }
  return i == s.size();
}

}  // namespace

double parse_scpi_number(std::string_view answer, const std::string& instrument, const std::string& command) {
  const std::string_view s = trim(answer);
  if (!is_nrf(s))
    throw ProtocolError(instrument, command,
                        fmt::format("expected a number, the answer was {}", quoted(answer)));
  // from_chars rejects a leading '+', which SCPI allows.
  const std::string_view digits = s.front() == '+' ? s.substr(1) : s;
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) {
    value = (digits.front() == '-' ? -1.0 : 1.0) * HUGE_VAL;
  } else if (ec != std::errc{} || ptr != digits.data() + digits.size()) {
    throw ProtocolError(instrument, command,
                        fmt::format("expected a number, the answer was {}", quoted(answer)));
  }
  return value;
}

ScpiErrorEntry parse_scpi_error(std::string_view answer, const std::string& instrument) {
  const std::string_view s = trim(answer);
  const auto comma = s.find(',');
  const auto bad = [&] {
    return ProtocolError(instrument, "SYST:ERR?",
                         fmt::format("expected <code>,\"<message>\", the answer was {}", quoted(answer)));
  };
  if (comma == std::string_view::npos) throw bad();
  const std::string_view code_text = trim(s.substr(0, comma));
  std::string_view text = trim(s.substr(comma + 1));
  int code = 0;
  const std::string_view code_digits =
      !code_text.empty() && code_text.front() == '+' ? code_text.substr(1) : code_text;
  const auto [ptr, ec] = std::from_chars(code_digits.data(), code_digits.data() + code_digits.size(), code);
  if (code_digits.empty() || ec != std::errc{} || ptr != code_digits.data() + code_digits.size()) throw bad();
  if (text.size() < 2 || text.front() != '"' || text.back() != '"') throw bad();
  text = text.substr(1, text.size() - 2);
  return {code, std::string(text)};
}

}  // namespace tocd::devices

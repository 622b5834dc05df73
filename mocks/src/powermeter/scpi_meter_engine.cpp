// SCPI engine of the simulated meter: header matching with short/long forms and optional
// nodes ("[SENSe]:CORRection:WAVelength" accepts SENS:CORR:WAV and CORRECTION:WAVELENGTH),
// an SCPI error queue, and readings = light + dark offset - zero + noise.
#include "powermeter/scpi_meter_engine.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace tocd::mocks::detail {
namespace {

constexpr double min_wavelength_nm = 400.0, max_wavelength_nm = 1100.0;  // S121C silicon sensor
constexpr double min_range_W = 1e-9;
constexpr std::size_t error_queue_size = 30;

struct Node {
  std::string short_form, long_form;
  bool optional = false;
};

std::vector<Node> parse_pattern(std::string_view p) {
  std::vector<Node> nodes;
  std::size_t i = 0;
  while (i < p.size()) {
    Node n;
    if (p[i] == '[') {
      n.optional = true;
      ++i;
    }
    if (i < p.size() && p[i] == ':') ++i;
    while (i < p.size() && p[i] != ':' && p[i] != '[' && p[i] != ']') {
      const char c = p[i++];
      if (std::isupper(static_cast<unsigned char>(c)) || c == '*' || c == '?') n.short_form += c;
      n.long_form += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    if (i < p.size() && p[i] == ']') ++i;
    nodes.push_back(std::move(n));
  }
  return nodes;
}

bool node_matches(const Node& n, std::string token) {
  // A numeric suffix selects a channel; the meter has one ("SENS1" = "SENS").
  while (token.size() > 1 && std::isdigit(static_cast<unsigned char>(token.back()))) token.pop_back();
  return token == n.short_form || token == n.long_form;
}

bool match(const std::vector<Node>& nodes, std::size_t i, const std::vector<std::string>& tokens,
           std::size_t j) {
  if (i == nodes.size()) return j == tokens.size();
  if (nodes[i].optional && match(nodes, i + 1, tokens, j)) return true;
  return j < tokens.size() && node_matches(nodes[i], tokens[j]) && match(nodes, i + 1, tokens, j + 1);
}

std::vector<std::string> tokenize(std::string_view header) {
  std::vector<std::string> tokens;
  if (!header.empty() && header.front() == ':') header.remove_prefix(1);
  std::size_t start = 0;
  for (;;) {
    const auto colon = header.find(':', start);
    std::string t(header.substr(start, colon - start));
    std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::toupper(c); });
    tokens.push_back(std::move(t));
    if (colon == std::string_view::npos) break;
    start = colon + 1;
  }
  return tokens;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::optional<double> to_number(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc{} || p != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string nr3(double v) {
  return fmt::format("{:.6E}", v);
}

}  // namespace

ScpiMeterEngine::ScpiMeterEngine(const PowerMeterTwinOptions& options) : o_(options), rng_(options.seed) {
  reset();
}

void ScpiMeterEngine::reset() {
  wavelength_nm_ = 635.0;
  auto_range_ = true;
  range_W_ = std::pow(10.0, std::ceil(std::log10(o_.max_power_W)));
  averaging_ = 1;
  configured_ = true;
  fetched_.reset();
  zeroing_ = false;  // the stored zero survives a reset, as on the real meter
}

void ScpiMeterEngine::push_error(int code, std::string message) {
  if (errors_.size() >= error_queue_size) {
    errors_.back() = {-350, "Queue overflow"};
    return;
  }
  errors_.emplace_back(code, std::move(message));
}

double ScpiMeterEngine::sample() {
  double light = o_.power_W ? std::max(0.0, o_.power_W()) : 0.0;
  if (o_.light_wavelength_nm)
    light *= *o_.light_wavelength_nm / wavelength_nm_;  // ideal Si responsivity ~ lambda
  const double sd =
      std::hypot(o_.noise_relative * light, o_.noise_floor_W) / std::sqrt(static_cast<double>(averaging_));
  std::normal_distribution<double> noise(0.0, sd);
  const double value = light + o_.dark_offset_W + noise(rng_) - zero_W_;
  if (force_over_range > 0) {
    --force_over_range;
    return 9.9e37;
  }
  if (light + o_.dark_offset_W > o_.max_power_W) return 9.9e37;
  if (auto_range_) {
    range_W_ = std::pow(10.0, std::ceil(std::log10(std::max(std::abs(value), min_range_W))));
  } else if (value > 1.1 * range_W_) {
    return 9.9e37;  // a fixed range saturates above 110 % of full scale
  }
  return value;
}

std::string ScpiMeterEngine::reading_text(double value) const {
  return nr3(value);
}

ScpiMeterEngine::Result ScpiMeterEngine::process(std::string_view message, std::int64_t now_ns) {
  Result r;
  std::string answers;
  std::size_t start = 0;
  for (;;) {
    const auto semi = message.find(';', start);
    const std::string_view unit = trim(message.substr(start, semi - start));
    if (!unit.empty()) {
      const auto space = unit.find_first_of(" \t");
      std::string_view header = unit.substr(0, space);
      const std::string_view params =
          space == std::string_view::npos ? std::string_view{} : trim(unit.substr(space));
      const bool query = !header.empty() && header.back() == '?';
      if (query) header.remove_suffix(1);
      Part p = run_one(header, params, query, now_ns);
      r.busy_s += p.busy_s;
      if (p.answer) {
        answers += (answers.empty() ? "" : ";") + *p.answer;
        r.numeric = p.numeric && !r.answer;
        r.answer = answers;
      }
    }
    if (semi == std::string_view::npos) break;
    start = semi + 1;
  }
  return r;
}

bool ScpiMeterEngine::Command::is(std::string_view pattern) const {
  return match(parse_pattern(pattern), 0, tokens, 0);
}

ScpiMeterEngine::Part ScpiMeterEngine::error(int code, const char* text) {
  push_error(code, text);
  return Part{};
}

ScpiMeterEngine::Part ScpiMeterEngine::run_one(std::string_view header, std::string_view params, bool query,
                                               std::int64_t now_ns) {
  const Command c{tokenize(header), params, query, now_ns};
  if (!query && header.empty()) return error(-102, "Syntax error");
  if (query && !params.empty() && !c.is("SYSTem:ERRor[:NEXT]")) return error(-108, "Parameter not allowed");
  if (zeroing_ && now_ns >= zero_done_ns_) {
    zeroing_ = false;
    zero_W_ = pending_zero_W_;
  }
  if (auto p = common_command(c)) return *p;
  if (auto p = settings_command(c)) return *p;
  if (auto p = reading_command(c)) return *p;
  return error(-113, "Undefined header");
}

std::optional<ScpiMeterEngine::Part> ScpiMeterEngine::common_command(const Command& c) {
  if (c.is("*IDN") && c.query)
    return Part{fmt::format("Thorlabs,{},{},{}", o_.model, o_.serial, o_.firmware)};
  if (c.is("*RST") && !c.query) return reset(), Part{};
  if (c.is("*CLS") && !c.query) return errors_.clear(), Part{};
  if (c.is("*OPC") && c.query) return Part{"1", 0.0, true};
  if (c.is("SYSTem:ERRor[:NEXT]") && c.query) {
    if (errors_.empty()) return Part{"0,\"No error\""};
    auto [code, text] = errors_.front();
    errors_.pop_front();
    return Part{fmt::format("{},\"{}\"", code, text)};
  }
  if (c.is("SYSTem:SENSor:IDN") && c.query) return Part{o_.sensor};
  return std::nullopt;
}

std::optional<ScpiMeterEngine::Part> ScpiMeterEngine::settings_command(const Command& c) {
  const auto number = [](double v) { return Part{nr3(v), 0.0, true}; };
  const auto integer = [](long v) { return Part{std::to_string(v), 0.0, true}; };
  if (c.is("[SENSe]:CORRection:WAVelength")) {
    if (c.query) return number(wavelength_nm_);
    if (c.params.empty()) return error(-109, "Missing parameter");
    const auto v = to_number(c.params);
    if (!v) return error(-104, "Data type error");
    if (*v < min_wavelength_nm || *v > max_wavelength_nm) return error(-222, "Data out of range");
    wavelength_nm_ = *v;
    return Part{};
  }
  if (c.is("[SENSe]:POWer[:DC]:RANGe:AUTO")) {
    if (c.query) return integer(auto_range_ ? 1 : 0);
    std::string p(c.params);
    std::transform(p.begin(), p.end(), p.begin(), [](unsigned char ch) { return std::toupper(ch); });
    if (p.empty()) return error(-109, "Missing parameter");
    if (p == "ON" || p == "1")
      auto_range_ = true;
    else if (p == "OFF" || p == "0")
      auto_range_ = false;
    else
      return error(-224, "Illegal parameter value");
    return Part{};
  }
  if (c.is("[SENSe]:POWer[:DC]:RANGe[:UPPer]")) {
    if (c.query) return number(range_W_);
    const auto v = to_number(c.params);
    if (!v || *v <= 0.0) return error(-224, "Illegal parameter value");
    auto_range_ = false;
    range_W_ = std::pow(10.0, std::ceil(std::log10(std::max(*v, min_range_W))));
    return Part{};
  }
  if (c.is("[SENSe]:AVERage[:COUNt]")) {
    if (c.query) return integer(averaging_);
    const auto v = to_number(c.params);
    if (!v || *v != std::floor(*v)) return error(-104, "Data type error");
    if (*v < 1 || *v > 1e6) return error(-222, "Data out of range");
    averaging_ = static_cast<int>(*v);
    return Part{};
  }
  if (c.is("[SENSe]:CORRection:COLLect:ZERO[:INITiate]") && !c.query) {
    // Zeroing averages the dark signal; the sensor is assumed covered, as the manual asks.
    std::normal_distribution<double> noise(0.0, o_.noise_floor_W / 30.0);
    pending_zero_W_ = o_.dark_offset_W + noise(rng_);
    zeroing_ = true;
    zero_done_ns_ = c.now_ns + static_cast<std::int64_t>(o_.zero_duration_s * 1e9);
    return Part{};
  }
  if (c.is("[SENSe]:CORRection:COLLect:ZERO:STATe") && c.query) return integer(zeroing_ ? 1 : 0);
  if (c.is("[SENSe]:CORRection:COLLect:ZERO:MAGNitude") && c.query) return number(zero_W_);
  if (c.is("[SENSe]:CORRection:COLLect:ZERO:ABORt") && !c.query) return zeroing_ = false, Part{};
  return std::nullopt;
}

std::optional<ScpiMeterEngine::Part> ScpiMeterEngine::reading_command(const Command& c) {
  const double sample_time = o_.sample_time_s * averaging_;
  if (c.is("MEASure[:SCALar][:POWer]") && c.query) {
    configured_ = true;
    return Part{reading_text(sample()), sample_time, true};
  }
  if (c.is("CONFigure[:SCALar][:POWer]")) {
    if (c.query) return Part{"POW"};
    configured_ = true;
    fetched_.reset();
    return Part{};
  }
  if (c.is("INITiate[:IMMediate]") && !c.query) {
    if (!configured_) return error(-221, "Settings conflict");
    fetched_ = sample();
    acquisition_done_ns_ = c.now_ns + static_cast<std::int64_t>(sample_time * 1e9);
    return Part{};
  }
  if (c.is("ABORt") && !c.query) return fetched_.reset(), Part{};
  if (c.is("FETCh[:SCALar][:POWer]") && c.query) {
    if (!fetched_) return error(-230, "Data corrupt or stale");
    const double wait = std::max(0.0, static_cast<double>(acquisition_done_ns_ - c.now_ns) * 1e-9);
    return Part{reading_text(*fetched_), wait, true};
  }
  if (c.is("READ[:SCALar][:POWer]") && c.query) {
    fetched_ = sample();
    return Part{reading_text(*fetched_), sample_time, true};
  }
  return std::nullopt;
}

}  // namespace tocd::mocks::detail

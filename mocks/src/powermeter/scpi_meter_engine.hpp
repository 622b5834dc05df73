#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "tocd/mocks/power_meter_twin.hpp"

namespace tocd::mocks::detail {

/// The SCPI command set and state of a PM100-class meter. Not thread-safe (the twin locks).
class ScpiMeterEngine {
 public:
  explicit ScpiMeterEngine(const PowerMeterTwinOptions& options);

  struct Result {
    std::optional<std::string> answer;  ///< without terminator; none for commands
    double busy_s = 0.0;                ///< simulated time the meter needs before answering
    bool numeric = false;               ///< the answer is one number
  };
  /// One program message (may hold several ';'-separated commands) at simulated time `now_ns`.
  Result process(std::string_view message, std::int64_t now_ns);

  void push_error(int code, std::string message);
  int force_over_range = 0;  ///< the next N readings answer 9.9E37

  double wavelength_nm() const { return wavelength_nm_; }
  int averaging() const { return averaging_; }
  bool auto_range() const { return auto_range_; }

 private:
  struct Part {
    std::optional<std::string> answer;
    double busy_s = 0.0;
    bool numeric = false;
  };
  /// One command of a program message: its header split into mnemonics, its parameters.
  struct Command {
    std::vector<std::string> tokens;
    std::string_view params;
    bool query = false;
    std::int64_t now_ns = 0;
    bool is(std::string_view pattern) const;  ///< the header matches this SCPI pattern
  };
  Part run_one(std::string_view header, std::string_view params, bool query, std::int64_t now_ns);
  // The command groups, tried in turn; none when the command is not of the group.
  std::optional<Part> common_command(const Command& c);    ///< IEEE 488.2 and SYSTem
  std::optional<Part> settings_command(const Command& c);  ///< SENSe settings and zeroing
  std::optional<Part> reading_command(const Command& c);   ///< MEASure, CONFigure, INIT, FETCh, READ
  Part error(int code, const char* text);
  void reset();
  double sample();  ///< one (averaged) reading as the meter would report it
  std::string reading_text(double value) const;

  PowerMeterTwinOptions o_;
  std::mt19937_64 rng_;
  std::deque<std::pair<int, std::string>> errors_;
  double wavelength_nm_ = 635.0;
  bool auto_range_ = true;
  double range_W_ = 1.0;
  int averaging_ = 1;
  double zero_W_ = 0.0, pending_zero_W_ = 0.0;
  std::int64_t zero_done_ns_ = 0;
  bool zeroing_ = false;
  bool configured_ = true;
  std::optional<double> fetched_;  ///< the value INIT acquired, for FETC?
  std::int64_t acquisition_done_ns_ = 0;
};

}  // namespace tocd::mocks::detail

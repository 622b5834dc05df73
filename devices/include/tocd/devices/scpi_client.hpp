#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tocd/devices/errors.hpp"
#include "tocd/devices/scpi_link.hpp"

namespace tocd::devices {

/// One entry of an SCPI error queue (`SYST:ERR?` answers `-222,"Data out of range"`).
struct ScpiErrorEntry {
  int code = 0;
  std::string message;
};

/// Strict SCPI <NR1>/<NR2>/<NR3> number: optional sign, digits, optional fraction, optional
/// exponent, surrounding blanks allowed, nothing else. Throws ProtocolError naming
/// `instrument`, `command` and the answer when `answer` is not such a number.
double parse_scpi_number(std::string_view answer, const std::string& instrument, const std::string& command);

/// Parses a `SYST:ERR?` answer; throws ProtocolError when it is not `<code>,"<text>"`.
ScpiErrorEntry parse_scpi_error(std::string_view answer, const std::string& instrument);

struct ScpiClientOptions {
  std::chrono::milliseconds timeout{2000};  ///< per attempt, write + read
  int retries = 2;                          ///< extra attempts after a timeout or a dropped link
  std::chrono::milliseconds backoff{50};    ///< first wait before a retry; doubles each time
  std::chrono::milliseconds max_backoff{1000};
  int max_error_drain = 32;  ///< SYST:ERR? calls at most per drain
};

/// Commands and queries over an ScpiLink with bounded waits, retries with exponential backoff,
/// reconnect after a dropped link, and error-queue checks. Every failure leaves as a
/// DeviceError subclass naming the instrument and the command. Not thread-safe.
class ScpiClient {
 public:
  ScpiClient(std::unique_ptr<ScpiLink> link, std::string instrument, ScpiClientOptions options = {});

  const std::string& instrument() const noexcept { return instrument_; }
  const ScpiClientOptions& options() const noexcept { return options_; }

  /// Sends a command that has no answer.
  void command(std::string_view cmd);
  /// Sends a query and returns its answer (printable ASCII, terminator stripped).
  /// `extra` lengthens the wait for slow queries (long averaging).
  std::string query(std::string_view q, std::chrono::milliseconds extra = std::chrono::milliseconds{0});
  /// A query whose answer must be one number.
  double query_number(std::string_view q, std::chrono::milliseconds extra = std::chrono::milliseconds{0});
  /// Reads SYST:ERR? until it answers 0; returns the entries seen (oldest first).
  std::vector<ScpiErrorEntry> drain_errors();
  /// Drains the error queue and raises InstrumentFault naming `after` if it held anything.
  void check_errors(std::string_view after);

  /// Counters for diagnostics and tests.
  int reconnects() const noexcept { return reconnects_; }
  int retried() const noexcept { return retried_; }

 private:
  std::string transact(std::string_view message, bool expect_answer, std::chrono::milliseconds extra);
  void ensure_open(Clock::time_point deadline);
  void recover_after_failure(LinkFailure kind) noexcept;
  std::optional<ScpiErrorEntry> probe_error() noexcept;

  std::unique_ptr<ScpiLink> link_;
  std::string instrument_;
  ScpiClientOptions options_;
  bool opened_once_ = false;
  int reconnects_ = 0;
  int retried_ = 0;
};

}  // namespace tocd::devices

#pragma once

#include <chrono>
#include <stdexcept>
#include <string>
#include <string_view>

namespace tocd::devices {

/// How a message link failed. Links report failures with this kind and a detail text; the
/// SCPI client turns them into DeviceError subclasses that name the instrument and command.
enum class LinkFailure { timeout, disconnected, protocol };

/// Failure of one ScpiLink operation (never escapes the drivers: ScpiClient translates it).
class LinkError : public std::runtime_error {
 public:
  LinkError(LinkFailure kind, const std::string& detail) : std::runtime_error(detail), kind_(kind) {}
  LinkFailure kind() const noexcept { return kind_; }

 private:
  LinkFailure kind_;
};

using Clock = std::chrono::steady_clock;

/// A message-based connection to an SCPI instrument: raw TCP (newline-terminated lines) or
/// USBTMC (bulk transfers with EOM). Every call is bounded by `deadline`. Not thread-safe.
class ScpiLink {
 public:
  virtual ~ScpiLink() = default;
  /// Where the link goes, e.g. "SCPI/TCP 127.0.0.1:5025" or "USBTMC 1313:8072 P0012345".
  virtual std::string describe() const = 0;
  /// (Re)connects; throws LinkError(disconnected) when the instrument cannot be reached.
  virtual void open(Clock::time_point deadline) = 0;
  virtual void close() noexcept = 0;
  virtual bool is_open() const noexcept = 0;
  /// Sends one program message; the link adds its terminator / EOM.
  virtual void write(std::string_view message, Clock::time_point deadline) = 0;
  /// Reads one response message, without its terminator.
  virtual std::string read(Clock::time_point deadline) = 0;
  /// Brings the link back to a known state after a timeout or a bad answer, so that no late
  /// answer is mistaken for the next one (TCP: reconnect; USBTMC: INITIATE_CLEAR).
  virtual void clear(Clock::time_point deadline) = 0;
};

}  // namespace tocd::devices

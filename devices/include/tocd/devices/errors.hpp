#pragma once

#include <string>

#include "tocd/core/error.hpp"

namespace tocd::devices {

/// Any failure talking to an instrument. The message names the instrument and the
/// register/command involved, e.g. "mechanical tester 127.0.0.1:1502: read of registers
/// 100..105 (position, load): timed out after 200 ms".
class DeviceError : public Error {
 public:
  DeviceError(std::string instrument, std::string operation, const std::string& what)
      : Error(instrument + ": " + operation + ": " + what),
        instrument_(std::move(instrument)),
        operation_(std::move(operation)) {}
  const std::string& instrument() const noexcept { return instrument_; }
  const std::string& operation() const noexcept { return operation_; }

 private:
  std::string instrument_;
  std::string operation_;
};

/// No (complete) answer within the bounded wait.
class TimeoutError : public DeviceError {
 public:
  using DeviceError::DeviceError;
};

/// The link is down (refused, dropped, cable pulled) and reconnecting did not help.
class ConnectionError : public DeviceError {
 public:
  using DeviceError::DeviceError;
};

/// The instrument answered, but not with what the protocol allows: bad CRC, short frame,
/// wrong slave id, wrong bTag, a number that is not a number, a Modbus exception.
class ProtocolError : public DeviceError {
 public:
  using DeviceError::DeviceError;
};

/// The instrument answered with a well-formed number that cannot be a measurement (a negative
/// optical power, SCPI's not-a-number code). The message quotes the answer.
class InvalidReading : public ProtocolError {
 public:
  using ProtocolError::ProtocolError;
};

/// The instrument reports a fault of its own (limit tripped, SCPI error queue entry, ...).
class InstrumentFault : public DeviceError {
 public:
  using DeviceError::DeviceError;
};

}  // namespace tocd::devices

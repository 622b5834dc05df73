#pragma once

#include <string>

namespace tocd::devices {

/// Where a Modbus TCP instrument listens.
struct ModbusTcpAddress {
  std::string host = "127.0.0.1";
  int port = 502;
  int slave_id = 1;  ///< MBAP unit identifier
};

/// A Modbus RTU instrument on a serial line (RS-485 adapter, USB-serial, or a pseudo-terminal).
struct ModbusRtuAddress {
  std::string device;  ///< e.g. /dev/ttyUSB0
  int baud = 19200;
  char parity = 'N';  ///< 'N', 'E' or 'O'
  int data_bits = 8;
  int stop_bits = 1;
  int slave_id = 1;
};

/// How hard a Modbus driver tries before it gives up. Every wait is bounded by timeout_s;
/// a failed transaction is retried `retries` times, sleeping backoff_s, 2 backoff_s, 4 backoff_s...
/// (capped at 1 s) in between, reconnecting first when the link dropped or timed out.
struct ModbusOptions {
  double timeout_s = 0.5;
  int retries = 2;
  double backoff_s = 0.02;
};

}  // namespace tocd::devices

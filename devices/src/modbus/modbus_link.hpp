#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "modbus/answer_deadline.hpp"
#include "tocd/devices/modbus_options.hpp"

struct _modbus;

namespace tocd::devices {

/// One Modbus client connection (TCP or RTU) with the error policy every tocdlab Modbus driver
/// shares: bounded waits, bounded retries with exponential backoff, reconnect after a dropped or
/// stalled link, and libmodbus errno values turned into typed DeviceErrors naming the
/// instrument and the registers. Not thread-safe.
class ModbusLink {
 public:
  struct Tcp {
    ModbusTcpAddress address;
  };
  struct Rtu {
    ModbusRtuAddress address;
  };

  ModbusLink(std::string instrument, const Tcp& tcp, const ModbusOptions& options);
  ModbusLink(std::string instrument, const Rtu& rtu, const ModbusOptions& options);
  ~ModbusLink();
  ModbusLink(const ModbusLink&) = delete;
  ModbusLink& operator=(const ModbusLink&) = delete;

  /// Opens the link (with retries); throws ConnectionError.
  void open();

  void read_input(int address, int count, std::uint16_t* dest, std::string_view what);
  void read_holding(int address, int count, std::uint16_t* dest, std::string_view what);
  void write_registers(int address, int count, const std::uint16_t* values, std::string_view what);
  void write_register(int address, std::uint16_t value, std::string_view what);

  const std::string& instrument() const noexcept { return instrument_; }
  int reconnects() const noexcept { return reconnects_; }

 private:
  void read_registers(int function, std::string_view table, int address, int count, std::uint16_t* dest,
                      std::string_view what);
  void transact(const std::string& operation, const std::function<int(_modbus*)>& call);
  bool connect_once(std::string& why);
  void drop();

  std::string instrument_;
  ModbusOptions options_;
  bool tcp_;
  std::string host_, service_;  // TCP only: for messages about name resolution
  AnswerDeadline answer_deadline_;
  _modbus* ctx_ = nullptr;
  bool connected_ = false;
  bool ever_connected_ = false;
  int reconnects_ = 0;
};

/// "registers 0..5 (position, load, status)"-style operation names.
std::string register_operation(std::string_view verb, std::string_view table, int address, int count,
                               std::string_view what);

}  // namespace tocd::devices

#pragma once

#include <cstdint>
#include <mutex>
#include <random>
#include <vector>

#include <modbus/modbus.h>

#include "modbus_server/fault_queue.hpp"

namespace tocd::mocks {

/// The holding-register range a write covers.
struct WriteRange {
  int address = 0, count = 0;
  bool touched(int reg) const { return reg >= address && reg < address + count; }
  /// Either register of the two-register float starting at `reg`.
  bool touched_float(int reg) const { return touched(reg) || touched(reg + 1); }
};

/// The holding registers as they would be after writing `values` over `range`.
std::vector<std::uint16_t> holding_after_write(const modbus_mapping_t& map, WriteRange range,
                                               const std::uint16_t* values);

/// A float over two registers at `at` (word order of devices/register_codec).
void put_float(std::uint16_t* regs, int at, double value);
float get_float(const std::uint16_t* regs, int at);

/// The instrument behind a Modbus server: keeps its registers current and acts on writes.
/// All three calls happen with the server's state mutex held.
class RegisterDevice {
 public:
  virtual ~RegisterDevice() = default;
  /// Advance the physics to now and publish it in the input registers.
  virtual void refresh(modbus_mapping_t& map) = 0;
  /// 0 to accept a write of `count` holding registers at `address`, or a Modbus exception code.
  virtual int check_write(const modbus_mapping_t& map, int address, int count,
                          const std::uint16_t* values) = 0;
  /// Act on a write that has been stored in the holding registers.
  virtual void after_write(modbus_mapping_t& map, int address, int count) = 0;
};

/// What a server does with one request.
struct ModbusAnswer {
  enum class Kind { send, silent, close };
  Kind kind = Kind::silent;
  std::vector<std::uint8_t> bytes;  ///< the whole ADU to send (Kind::send)
  double delay_s = 0.0;             ///< real seconds before it leaves (an injected delay)
};

/// Serves one complete request ADU as received: for TCP the MBAP header (7 bytes) and the PDU,
/// its length already checked by the caller; for RTU the slave id, the PDU and the CRC, already
/// checked by libmodbus. Every register write passes RegisterDevice::check_write before it is
/// stored, whatever function code carries it; the next injected fault applies.
ModbusAnswer serve_request(bool tcp, const std::uint8_t* adu, int length, modbus_mapping_t& map,
                           RegisterDevice& device, std::mutex& state_mutex, FaultQueue& faults,
                           std::mt19937_64& rng);

/// CRC-16/MODBUS of a frame (transmitted low byte first).
std::uint16_t modbus_crc16(const std::uint8_t* data, std::size_t n);

}  // namespace tocd::mocks

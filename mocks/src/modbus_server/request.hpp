#pragma once

#include <cstdint>
#include <vector>

#include <modbus/modbus.h>

namespace tocd::mocks {

/// One Modbus request PDU, decoded and checked against the register map. Only the function
/// codes the simulated instruments document are served: 0x03 read holding registers, 0x04 read
/// input registers, 0x06 write single register, 0x10 write multiple registers. Anything else
/// (mask write 0x16, read/write 0x17, coils, diagnostics, ...) is refused with exception 1, so
/// no function code can change a register without the instrument's own checks.
struct ModbusRequest {
  int function = 0, address = 0, count = 0;
  std::vector<std::uint16_t> values;  ///< for writes
  /// 0, or the Modbus exception that answers the request: 1 illegal function, 2 illegal data
  /// address (outside the map), 3 illegal data value (malformed, or a count out of range).
  int exception = 0;

  bool is_write() const {
    return function == MODBUS_FC_WRITE_SINGLE_REGISTER || function == MODBUS_FC_WRITE_MULTIPLE_REGISTERS;
  }
  bool is_read() const {
    return function == MODBUS_FC_READ_HOLDING_REGISTERS || function == MODBUS_FC_READ_INPUT_REGISTERS;
  }
};

/// Decodes the PDU `pdu`[0..`length`) (function code first) against `map`.
ModbusRequest parse_request(const std::uint8_t* pdu, int length, const modbus_mapping_t& map);

/// The answer PDU of a request served normally (read data, or the write echo); `registers`
/// read registers are included (fewer than asked for makes a short frame on purpose).
std::vector<std::uint8_t> answer_pdu(const ModbusRequest& r, const modbus_mapping_t& map, int registers);

/// An exception answer PDU.
std::vector<std::uint8_t> exception_pdu(int function, int code);

/// Appends v to out in Modbus's byte order (big-endian).
inline void put_be16(std::vector<std::uint8_t>& out, std::uint16_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v & 0xFF));
}

}  // namespace tocd::mocks

// Decoding and checking of the Modbus requests the simulated instruments serve; the limits on
// counts are those of the Modbus application protocol (and of libmodbus).
#include "modbus_server/request.hpp"

namespace tocd::mocks {

namespace {

std::uint16_t be16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}

constexpr int illegal_function = 1, illegal_address = 2, illegal_value = 3;

}  // namespace

ModbusRequest parse_request(const std::uint8_t* pdu, int length, const modbus_mapping_t& map) {
  ModbusRequest r;
  if (length < 1) {
    r.exception = illegal_value;
    return r;
  }
  r.function = pdu[0];
  if (!r.is_read() && !r.is_write()) {
    r.exception = illegal_function;
    return r;
  }
  if (length < 5) {
    r.exception = illegal_value;
    return r;
  }
  r.address = be16(pdu + 1);
  int table_size = map.nb_registers;
  switch (r.function) {
    case MODBUS_FC_READ_INPUT_REGISTERS:
      table_size = map.nb_input_registers;
      [[fallthrough]];
    case MODBUS_FC_READ_HOLDING_REGISTERS:
      r.count = be16(pdu + 3);
      if (length != 5 || r.count < 1 || r.count > MODBUS_MAX_READ_REGISTERS) r.exception = illegal_value;
      break;
    case MODBUS_FC_WRITE_SINGLE_REGISTER:
      r.count = 1;
      r.values = {be16(pdu + 3)};
      if (length != 5) r.exception = illegal_value;
      break;
    case MODBUS_FC_WRITE_MULTIPLE_REGISTERS:
      r.count = be16(pdu + 3);
      if (length < 6 || r.count < 1 || r.count > MODBUS_MAX_WRITE_REGISTERS || pdu[5] != 2 * r.count ||
          length != 6 + 2 * r.count) {
        r.exception = illegal_value;
        break;
      }
      for (int i = 0; i < r.count; ++i) r.values.push_back(be16(pdu + 6 + 2 * i));
      break;
  }
  if (r.exception == 0 && r.address + r.count > table_size) r.exception = illegal_address;
  return r;
}

std::vector<std::uint8_t> answer_pdu(const ModbusRequest& r, const modbus_mapping_t& map, int registers) {
  std::vector<std::uint8_t> pdu{static_cast<std::uint8_t>(r.function)};
  if (r.is_read()) {
    const bool input = r.function == MODBUS_FC_READ_INPUT_REGISTERS;
    const std::uint16_t* table = input ? map.tab_input_registers : map.tab_registers;
    const int size = input ? map.nb_input_registers : map.nb_registers;
    pdu.push_back(static_cast<std::uint8_t>(2 * registers));
    for (int i = 0; i < registers; ++i) put_be16(pdu, r.address + i < size ? table[r.address + i] : 0);
  } else if (r.function == MODBUS_FC_WRITE_SINGLE_REGISTER) {
    put_be16(pdu, static_cast<std::uint16_t>(r.address));
    put_be16(pdu, r.values.at(0));
  } else {
    put_be16(pdu, static_cast<std::uint16_t>(r.address));
    put_be16(pdu, static_cast<std::uint16_t>(r.count));
  }
  return pdu;
}

std::vector<std::uint8_t> exception_pdu(int function, int code) {
  return {static_cast<std::uint8_t>(function | 0x80), static_cast<std::uint8_t>(code)};
}

}  // namespace tocd::mocks

// Request handling shared by the Modbus twins: every answer, normal or faulty, is framed here
// (nothing is sent from this file: the transport decides when and how), and every register
// write goes through the instrument's check_write whatever function code carries it.
#include "modbus_server/register_server.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "modbus_server/request.hpp"
#include "tocd/devices/register_codec.hpp"

namespace tocd::mocks {

std::vector<std::uint16_t> holding_after_write(const modbus_mapping_t& map, WriteRange range,
                                               const std::uint16_t* values) {
  std::vector<std::uint16_t> hr(map.tab_registers, map.tab_registers + map.nb_registers);
  std::copy(values, values + range.count, hr.begin() + range.address);
  return hr;
}

void put_float(std::uint16_t* regs, int at, double value) {
  const auto r = devices::float_to_registers(static_cast<float>(value));
  regs[at] = r[0];
  regs[at + 1] = r[1];
}

float get_float(const std::uint16_t* regs, int at) {
  return devices::registers_to_float(regs[at], regs[at + 1]);
}
namespace {

// Bytes before the PDU (MBAP header; slave id) and after it (CRC) in an ADU.
constexpr int tcp_header_length = 7, rtu_header_length = 1, rtu_crc_length = 2;

/// Wraps a PDU in the transport's framing, answering as `slave`.
std::vector<std::uint8_t> frame(bool tcp, const std::uint8_t* req, std::uint8_t slave,
                                const std::vector<std::uint8_t>& pdu, bool corrupt_crc) {
  std::vector<std::uint8_t> out;
  if (tcp) {
    out.push_back(req[0]);  // transaction id
    out.push_back(req[1]);
    put_be16(out, 0);  // protocol id
    put_be16(out, static_cast<std::uint16_t>(pdu.size() + 1));
    out.push_back(slave);
    for (const auto b : pdu) out.push_back(b);
    return out;
  }
  out.push_back(slave);
  for (const auto b : pdu) out.push_back(b);
  std::uint16_t crc = modbus_crc16(out.data(), out.size());
  if (corrupt_crc) crc ^= 0x5A5A;
  out.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  out.push_back(static_cast<std::uint8_t>(crc >> 8));
  return out;
}

/// Stores a checked write and lets the instrument act on it.
void apply_write(const ModbusRequest& r, modbus_mapping_t& map, RegisterDevice& device) {
  for (int i = 0; i < r.count; ++i) map.tab_registers[r.address + i] = r.values[i];
  device.after_write(map, r.address, r.count);
}

}  // namespace

std::uint16_t modbus_crc16(const std::uint8_t* data, std::size_t n) {
  std::uint16_t crc = 0xFFFF;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int b = 0; b < 8; ++b) crc = (crc & 1) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001) : crc >> 1;
  }
  return crc;
}

ModbusAnswer serve_request(bool tcp, const std::uint8_t* adu, int length, modbus_mapping_t& map,
                           RegisterDevice& device, std::mutex& state_mutex, FaultQueue& faults,
                           std::mt19937_64& rng) {
  using K = ModbusFaultKind;
  using Kind = ModbusAnswer::Kind;
  const int header = tcp ? tcp_header_length : rtu_header_length;
  const int pdu_length = length - header - (tcp ? 0 : rtu_crc_length);
  const std::uint8_t slave = adu[header - 1];
  ModbusAnswer a;
  const auto fault = faults.take();
  if (fault && fault->kind == K::drop_connection) {
    a.kind = Kind::close;
    return a;
  }
  if (fault && fault->kind == K::no_reply) return a;
  if (fault && fault->kind == K::delay_reply) a.delay_s = fault->delay_s;
  // A broadcast on a serial line is acted on and never answered, not even with an exception:
  // every slave on the line would answer at once (Modbus over serial line, 2.2).
  const bool broadcast = !tcp && slave == MODBUS_BROADCAST_ADDRESS;
  const auto send = [&](const std::vector<std::uint8_t>& pdu, std::uint8_t as_slave = 0,
                        bool bad_crc = false) {
    if (broadcast) return a;
    a.kind = Kind::send;
    a.bytes = frame(tcp, adu, as_slave ? as_slave : slave, pdu, bad_crc);
    return a;
  };

  std::lock_guard lock(state_mutex);
  device.refresh(map);
  const ModbusRequest r = parse_request(adu + header, pdu_length, map);
  if (r.exception) return send(exception_pdu(r.function, r.exception));
  if (r.is_write())
    if (const int exc = device.check_write(map, r.address, r.count, r.values.data()))
      return send(exception_pdu(r.function, exc));
  if (!fault || fault->kind == K::delay_reply || (fault->kind == K::nan_value && r.is_write())) {
    if (r.is_write()) apply_write(r, map, device);
    return send(answer_pdu(r, map, r.count));
  }
  switch (fault->kind) {
    case K::exception:
      return send(exception_pdu(r.function, fault->exception_code));
    case K::garbage: {
      a.kind = Kind::send;
      a.bytes.resize(9 + rng() % 8);
      for (auto& b : a.bytes) b = static_cast<std::uint8_t>(rng());
      return a;
    }
    case K::nan_value: {
      const auto nan = tocd::devices::float_to_registers(std::numeric_limits<float>::quiet_NaN());
      std::vector<std::uint8_t> pdu = answer_pdu(r, map, r.count);
      for (int i = 0; i < std::min(2, r.count); ++i) {
        pdu[2 + 2 * i] = static_cast<std::uint8_t>(nan[i] >> 8);
        pdu[3 + 2 * i] = static_cast<std::uint8_t>(nan[i] & 0xFF);
      }
      return send(pdu);
    }
    default:
      break;
  }
  // The remaining faults answer an applied request with a defective frame.
  if (r.is_write()) apply_write(r, map, device);
  switch (fault->kind) {
    case K::bad_crc:
      return send(answer_pdu(r, map, r.count), 0, true);
    case K::wrong_slave:
      return send(answer_pdu(r, map, r.count), static_cast<std::uint8_t>(slave % 247 + 1));
    case K::short_frame: {
      auto pdu = answer_pdu(r, map, r.is_read() ? std::max(0, r.count - 1) : r.count);
      if (!r.is_read()) pdu.resize(3);
      return send(pdu);
    }
    case K::truncated_frame: {
      send(answer_pdu(r, map, r.count));
      a.bytes.resize(a.bytes.size() / 2);
      return a;
    }
    default:
      return send(answer_pdu(r, map, r.count));
  }
}

}  // namespace tocd::mocks

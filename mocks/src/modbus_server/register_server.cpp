// Request handling shared by the Modbus twins: the normal path goes through libmodbus'
// modbus_reply; faulty answers are framed by hand so that every byte of the defect is ours.
#include "modbus_server/register_server.hpp"

#include <chrono>
#include <cstring>
#include <limits>
#include <thread>
#include <vector>

#include <sys/socket.h>
#include <unistd.h>

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

struct Request {
  int function = 0, address = 0, count = 0;
  std::vector<std::uint16_t> values;  // for writes
  bool valid = false;
};

std::uint16_t be16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}

Request parse(const std::uint8_t* req, int length, int hl) {
  Request r;
  if (length < hl + 5) return r;
  r.function = req[hl];
  r.address = be16(req + hl + 1);
  switch (r.function) {
    case MODBUS_FC_READ_HOLDING_REGISTERS:
    case MODBUS_FC_READ_INPUT_REGISTERS:
      r.count = be16(req + hl + 3);
      break;
    case MODBUS_FC_WRITE_SINGLE_REGISTER:
      r.count = 1;
      r.values = {be16(req + hl + 3)};
      break;
    case MODBUS_FC_WRITE_MULTIPLE_REGISTERS:
      r.count = be16(req + hl + 3);
      if (length < hl + 6 + 2 * r.count) return r;
      for (int i = 0; i < r.count; ++i) r.values.push_back(be16(req + hl + 6 + 2 * i));
      break;
    default:
      return r;
  }
  r.valid = true;
  return r;
}

void put16(std::vector<std::uint8_t>& out, std::uint16_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v & 0xFF));
}

/// Wraps a PDU in the transport's framing, answering as `slave`.
std::vector<std::uint8_t> frame(bool tcp, const std::uint8_t* req, std::uint8_t slave,
                                const std::vector<std::uint8_t>& pdu, bool corrupt_crc) {
  std::vector<std::uint8_t> out;
  if (tcp) {
    out.push_back(req[0]);  // transaction id
    out.push_back(req[1]);
    put16(out, 0);  // protocol id
    put16(out, static_cast<std::uint16_t>(pdu.size() + 1));
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

std::vector<std::uint8_t> reply_pdu(const Request& r, const modbus_mapping_t& map, int registers) {
  std::vector<std::uint8_t> pdu{static_cast<std::uint8_t>(r.function)};
  if (r.function == MODBUS_FC_READ_HOLDING_REGISTERS || r.function == MODBUS_FC_READ_INPUT_REGISTERS) {
    const bool input = r.function == MODBUS_FC_READ_INPUT_REGISTERS;
    const std::uint16_t* table = input ? map.tab_input_registers : map.tab_registers;
    const int size = input ? map.nb_input_registers : map.nb_registers;
    pdu.push_back(static_cast<std::uint8_t>(2 * registers));
    for (int i = 0; i < registers; ++i) put16(pdu, r.address + i < size ? table[r.address + i] : 0);
  } else if (r.function == MODBUS_FC_WRITE_SINGLE_REGISTER) {
    put16(pdu, static_cast<std::uint16_t>(r.address));
    put16(pdu, r.values.at(0));
  } else {
    put16(pdu, static_cast<std::uint16_t>(r.address));
    put16(pdu, static_cast<std::uint16_t>(r.count));
  }
  return pdu;
}

void send_bytes(int fd, bool tcp, const std::vector<std::uint8_t>& bytes) {
  ssize_t rc =
      tcp ? ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) : ::write(fd, bytes.data(), bytes.size());
  (void)rc;  // a client that went away is the client's problem
}

bool in_range(const Request& r, const modbus_mapping_t& map) {
  const bool input = r.function == MODBUS_FC_READ_INPUT_REGISTERS;
  const int size = input ? map.nb_input_registers : map.nb_registers;
  return r.count >= 1 && r.address + r.count <= size;
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

bool serve_request(modbus_t* ctx, int fd, bool tcp, const std::uint8_t* req, int length,
                   modbus_mapping_t& map, RegisterDevice& device, std::mutex& state_mutex, FaultQueue& faults,
                   std::mt19937_64& rng) {
  const int hl = modbus_get_header_length(ctx);
  const Request r = parse(req, length, hl);
  const auto fault = faults.take();
  using K = ModbusFaultKind;
  if (fault && fault->kind == K::delay_reply)
    std::this_thread::sleep_for(std::chrono::duration<double>(fault->delay_s));
  if (fault && fault->kind == K::drop_connection) return false;
  if (fault && fault->kind == K::no_reply) return true;

  std::lock_guard lock(state_mutex);
  device.refresh(map);
  const bool is_write = r.valid && (r.function == MODBUS_FC_WRITE_SINGLE_REGISTER ||
                                    r.function == MODBUS_FC_WRITE_MULTIPLE_REGISTERS);
  if (is_write && in_range(r, map)) {
    if (const int exc = device.check_write(map, r.address, r.count, r.values.data())) {
      modbus_reply_exception(ctx, req, exc);
      return true;
    }
  }
  const auto slave = req[hl - 1];
  if (!fault || fault->kind == K::delay_reply || !r.valid || !in_range(r, map) ||
      (fault->kind == K::nan_value && is_write)) {
    modbus_reply(ctx, req, length, &map);
    if (is_write && in_range(r, map)) device.after_write(map, r.address, r.count);
    return true;
  }
  switch (fault->kind) {
    case K::exception:
      modbus_reply_exception(ctx, req, fault->exception_code);
      return true;
    case K::garbage: {
      std::vector<std::uint8_t> junk(9 + rng() % 8);
      for (auto& b : junk) b = static_cast<std::uint8_t>(rng());
      send_bytes(fd, tcp, junk);
      return true;
    }
    case K::nan_value: {
      const auto nan = tocd::devices::float_to_registers(std::numeric_limits<float>::quiet_NaN());
      std::vector<std::uint8_t> pdu = reply_pdu(r, map, r.count);
      for (int i = 0; i < std::min(2, r.count); ++i) {
        pdu[2 + 2 * i] = static_cast<std::uint8_t>(nan[i] >> 8);
        pdu[3 + 2 * i] = static_cast<std::uint8_t>(nan[i] & 0xFF);
      }
      send_bytes(fd, tcp, frame(tcp, req, slave, pdu, false));
      return true;
    }
    default:
      break;
  }
  // The remaining faults answer a (possibly applied) request with a defective frame.
  if (is_write) {
    for (int i = 0; i < r.count; ++i) map.tab_registers[r.address + i] = r.values[i];
    device.after_write(map, r.address, r.count);
  }
  const bool reading = !is_write;
  switch (fault->kind) {
    case K::bad_crc:
      send_bytes(fd, tcp, frame(tcp, req, slave, reply_pdu(r, map, r.count), true));
      break;
    case K::wrong_slave:
      send_bytes(
          fd, tcp,
          frame(tcp, req, static_cast<std::uint8_t>(slave % 247 + 1), reply_pdu(r, map, r.count), false));
      break;
    case K::short_frame: {
      auto pdu = reply_pdu(r, map, reading ? std::max(0, r.count - 1) : r.count);
      if (!reading) pdu.resize(3);
      send_bytes(fd, tcp, frame(tcp, req, slave, pdu, false));
      break;
    }
    case K::truncated_frame: {
      auto bytes = frame(tcp, req, slave, reply_pdu(r, map, r.count), false);
      bytes.resize(bytes.size() / 2);
      send_bytes(fd, tcp, bytes);
      break;
    }
    default:
      modbus_reply(ctx, req, length, &map);
      break;
  }
  return true;
}

}  // namespace tocd::mocks

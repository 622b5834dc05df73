// USBTMC 1.0 bulk headers (spec section 3.2): 12 bytes, little-endian sizes, every transfer
// padded with zeros to a multiple of 4.
#include <fmt/format.h>

#include "tocd/devices/usbtmc.hpp"

namespace tocd::devices::usbtmc {
namespace {

void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

std::uint32_t get_u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

std::string hex(std::span<const std::uint8_t> bytes) {
  std::string out;
  for (auto b : bytes) out += fmt::format("{}{:02X}", out.empty() ? "" : " ", b);
  return out;
}

[[noreturn]] void bad(std::span<const std::uint8_t> t, const std::string& what) {
  throw LinkError(LinkFailure::protocol,
                  fmt::format("bad USBTMC DEV_DEP_MSG_IN: {} (header bytes: {})", what,
                              hex(t.first(std::min<std::size_t>(t.size(), header_size)))));
}

}  // namespace

std::vector<std::uint8_t> encode_dev_dep_msg_out(std::uint8_t tag, std::span<const std::uint8_t> payload,
                                                 bool eom) {
  const std::size_t padded = (header_size + payload.size() + 3) / 4 * 4;
  std::vector<std::uint8_t> t(padded, 0);
  t[0] = dev_dep_msg_out;
  t[1] = tag;
  t[2] = static_cast<std::uint8_t>(~tag);
  put_u32(&t[4], static_cast<std::uint32_t>(payload.size()));
  t[8] = eom ? 0x01 : 0x00;
  std::copy(payload.begin(), payload.end(), t.begin() + header_size);
  return t;
}

std::array<std::uint8_t, header_size> encode_request_dev_dep_msg_in(std::uint8_t tag,
                                                                    std::uint32_t max_size) {
  std::array<std::uint8_t, header_size> t{};
  t[0] = request_dev_dep_msg_in;
  t[1] = tag;
  t[2] = static_cast<std::uint8_t>(~tag);
  put_u32(&t[4], max_size);
  return t;  // bmTransferAttributes 0: no TermChar
}

InHeader decode_dev_dep_msg_in(std::span<const std::uint8_t> t, std::uint8_t expected_tag,
                               std::uint32_t requested) {
  if (t.size() < header_size)
    bad(t, fmt::format("transfer of {} bytes is shorter than the 12-byte header", t.size()));
  if (t[0] != dev_dep_msg_in) bad(t, fmt::format("MsgID {} (expected 2, DEV_DEP_MSG_IN)", t[0]));
  if (t[1] != expected_tag)
    bad(t, fmt::format("bTag {} does not echo the request's bTag {}", t[1], expected_tag));
  if (t[2] != static_cast<std::uint8_t>(~t[1]))
    bad(t, fmt::format("bTagInverse 0x{:02X} is not the inverse of bTag 0x{:02X}", t[2], t[1]));
  if (t[3] != 0 || t[9] != 0 || t[10] != 0 || t[11] != 0) bad(t, "reserved header bytes are not zero");
  InHeader h;
  h.tag = t[1];
  h.transfer_size = get_u32(&t[4]);
  h.eom = (t[8] & 0x01) != 0;
  if ((t[8] & ~0x01) != 0) bad(t, fmt::format("undefined bmTransferAttributes bits 0x{:02X}", t[8]));
  if (h.transfer_size > requested)
    bad(t, fmt::format("TransferSize {} exceeds the {} bytes requested", h.transfer_size, requested));
  if (t.size() < header_size + h.transfer_size)
    bad(t, fmt::format("TransferSize {} but only {} data bytes arrived", h.transfer_size,
                       t.size() - header_size));
  return h;
}

}  // namespace tocd::devices::usbtmc

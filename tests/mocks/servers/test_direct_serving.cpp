// TesterTwin::serve_stream and VacuumTwin::serve_frame: the twins' own request handling
// without a socket or a pseudo-terminal (what the fuzz targets call), checked against frames
// built here from the Modbus specifications.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tocd/devices/register_codec.hpp"
#include "tocd/devices/tester_registers.hpp"
#include "tocd/devices/vacuum_registers.hpp"
#include "tocd/mocks/tester_twin.hpp"
#include "tocd/mocks/vacuum_twin.hpp"

namespace {

using tocd::mocks::TesterTwin;
using tocd::mocks::VacuumTwin;
using Bytes = std::vector<std::uint8_t>;

// Modbus TCP: transaction id, protocol id 0, length (unit id + PDU), unit id, PDU.
std::string mbap(std::uint16_t transaction, const Bytes& pdu, std::uint16_t protocol = 0) {
  const auto length = static_cast<std::uint16_t>(pdu.size() + 1);
  std::string f{static_cast<char>(transaction >> 8),
                static_cast<char>(transaction & 0xFF),
                static_cast<char>(protocol >> 8),
                static_cast<char>(protocol & 0xFF),
                static_cast<char>(length >> 8),
                static_cast<char>(length & 0xFF),
                1};
  f.append(pdu.begin(), pdu.end());
  return f;
}

// CRC-16/MODBUS as the serial line specification defines it (reflected 0xA001, start 0xFFFF).
std::uint16_t crc16(std::span<const std::uint8_t> b) {
  std::uint16_t crc = 0xFFFF;
  for (const std::uint8_t x : b) {
    crc ^= x;
    for (int i = 0; i < 8; ++i) crc = (crc & 1) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001) : crc >> 1;
  }
  return crc;
}

Bytes rtu(std::uint8_t slave, const Bytes& pdu) {
  Bytes f{slave};
  f.insert(f.end(), pdu.begin(), pdu.end());
  const std::uint16_t crc = crc16(f);
  f.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  f.push_back(static_cast<std::uint8_t>(crc >> 8));
  return f;
}

Bytes read_holding(int address, int count) {
  return {0x03, 0, static_cast<std::uint8_t>(address), 0, static_cast<std::uint8_t>(count)};
}

Bytes write_float(int address, float value) {
  const auto regs = tocd::devices::float_to_registers(value);
  return {0x10,
          0,
          static_cast<std::uint8_t>(address),
          0,
          2,
          4,
          static_cast<std::uint8_t>(regs[0] >> 8),
          static_cast<std::uint8_t>(regs[0] & 0xFF),
          static_cast<std::uint8_t>(regs[1] >> 8),
          static_cast<std::uint8_t>(regs[1] & 0xFF)};
}

float float_at(const std::uint8_t* p) {
  return tocd::devices::registers_to_float(static_cast<std::uint16_t>((p[0] << 8) | p[1]),
                                           static_cast<std::uint16_t>((p[2] << 8) | p[3]));
}

}  // namespace

TEST(DirectServing, TesterAnswersPipelinedFramesAndKeepsAnIncompleteOne) {
  tocd::mocks::TesterTwinOptions o;
  o.physics.max_travel_mm = 7.5;
  TesterTwin tester(o);
  namespace m = tocd::devices::tester_map;
  const std::string first = mbap(0x1234, read_holding(m::hr_max_travel, 2));
  const std::string second = mbap(0x1235, read_holding(m::hr_max_travel, 2));
  const auto reply = tester.serve_stream(first + second + second.substr(0, 5));
  EXPECT_FALSE(reply.closed);
  // Two answers of 6 + 1 + (1 + 1 + 4) bytes: function 3, byte count 4, one float.
  ASSERT_EQ(reply.sent.size(), 2u * 13u);
  const auto* a = reinterpret_cast<const std::uint8_t*>(reply.sent.data());
  EXPECT_EQ(a[0], 0x12);
  EXPECT_EQ(a[1], 0x34);
  EXPECT_EQ(a[5], 7);  // length: unit id + 6 PDU bytes
  EXPECT_EQ(a[7], 0x03);
  EXPECT_EQ(a[8], 4);
  EXPECT_FLOAT_EQ(float_at(a + 9), 7.5F);
  EXPECT_EQ(a[13 + 1], 0x35);
}

TEST(DirectServing, TesterClosesOnAFrameThatIsNotModbusTcp) {
  TesterTwin tester;
  namespace m = tocd::devices::tester_map;
  const auto reply = tester.serve_stream(mbap(1, read_holding(m::hr_max_travel, 2), /*protocol=*/1));
  EXPECT_TRUE(reply.closed);
  EXPECT_TRUE(reply.sent.empty());
}

TEST(DirectServing, VacuumAnswersItsSlaveIdWithAGoodCrcAndIgnoresTheRest) {
  VacuumTwin vacuum;
  namespace m = tocd::devices::vacuum_map;
  const Bytes answer = vacuum.serve_frame(rtu(1, read_holding(m::hr_setpoint, 2)));
  ASSERT_EQ(answer.size(), 1u + 2u + 4u + 2u);
  EXPECT_EQ(answer[0], 1);
  EXPECT_EQ(answer[1], 0x03);
  EXPECT_EQ(crc16(std::span(answer).first(answer.size() - 2)),
            answer[answer.size() - 2] | (answer[answer.size() - 1] << 8));

  Bytes bad_crc = rtu(1, read_holding(m::hr_setpoint, 2));
  bad_crc.back() ^= 0xFF;
  EXPECT_TRUE(vacuum.serve_frame(bad_crc).empty());
  EXPECT_TRUE(vacuum.serve_frame(rtu(9, read_holding(m::hr_setpoint, 2))).empty());
  EXPECT_TRUE(vacuum.serve_frame(Bytes{1, 3, 0}).empty());
}

TEST(DirectServing, VacuumActsOnABroadcastWithoutAnswering) {
  VacuumTwin vacuum;
  namespace m = tocd::devices::vacuum_map;
  EXPECT_TRUE(vacuum.serve_frame(rtu(0, write_float(m::hr_setpoint, 42.0F))).empty());
  // Not even a request the controller refuses is answered (found by the vacuum_modbus fuzz
  // target: an illegal function broadcast got an exception answer).
  EXPECT_TRUE(vacuum.serve_frame(rtu(0, Bytes{0xFF, 0, 0, 0, 0})).empty());
  EXPECT_TRUE(vacuum.serve_frame(rtu(0, read_holding(m::hr_setpoint, 2))).empty());
  const Bytes answer = vacuum.serve_frame(rtu(1, read_holding(m::hr_setpoint, 2)));
  ASSERT_EQ(answer.size(), 9u);
  EXPECT_FLOAT_EQ(float_at(answer.data() + 3), 42.0F);
}

// The tester twin's Modbus request handling, byte by byte: only the documented function codes,
// every register write through the same checks, malformed frames.
#include <chrono>
#include <memory>
#include <thread>

#include <gtest/gtest.h>

#include "raw_client.hpp"
#include "tocd/devices/register_codec.hpp"
#include "tocd/devices/tester_registers.hpp"
#include "tocd/mocks/sim_clock.hpp"
#include "tocd/mocks/tester_twin.hpp"

namespace m = tocd::devices::tester_map;
using servertest::modbus_call;
using servertest::RawClient;
using Pdu = std::vector<std::uint8_t>;

namespace {

std::uint8_t hi(int v) {
  return static_cast<std::uint8_t>((v >> 8) & 0xFF);
}
std::uint8_t lo(int v) {
  return static_cast<std::uint8_t>(v & 0xFF);
}

class ModbusRequests : public ::testing::Test {
 protected:
  void SetUp() override {
    tocd::mocks::TesterTwinOptions o;
    o.clock = std::make_shared<tocd::mocks::SimClock>(50.0);
    o.physics.tissue = tocd::mocks::make_analytic_tissue(2.5);
    o.physics.load_noise_N = 0.0;
    twin_ = std::make_unique<tocd::mocks::TesterTwin>(o);
    client_ = std::make_unique<RawClient>(twin_->port());
    ASSERT_TRUE(client_->connected());
  }

  Pdu call(const Pdu& pdu) {
    auto a = modbus_call(*client_, pdu);
    EXPECT_TRUE(a.has_value()) << "no answer to function " << int(pdu.at(0));
    return a.value_or(Pdu{});
  }

  std::vector<std::uint16_t> holding(int address, int count) {
    const Pdu a = call({3, hi(address), lo(address), hi(count), lo(count)});
    std::vector<std::uint16_t> regs;
    for (int i = 0; i < count && 3 + 2 * i < static_cast<int>(a.size()); ++i)
      regs.push_back(static_cast<std::uint16_t>((a[2 + 2 * i] << 8) | a[3 + 2 * i]));
    return regs;
  }

  float load_limit() {
    const auto r = holding(m::hr_max_load, 2);
    return r.size() == 2 ? tocd::devices::registers_to_float(r[0], r[1]) : -1.0f;
  }

  std::unique_ptr<tocd::mocks::TesterTwin> twin_;
  std::unique_ptr<RawClient> client_;
};

Pdu exception(int fc, int code) {
  return {static_cast<std::uint8_t>(fc | 0x80), static_cast<std::uint8_t>(code)};
}

}  // namespace

// Mask write (0x16) and read/write multiple (0x17) used to reach the registers without the
// tester's checks (a NaN load limit was stored); they and every other undocumented function
// now answer exception 1 and change nothing.
TEST_F(ModbusRequests, UndocumentedFunctionCodesAnswerIllegalFunctionAndChangeNothing) {
  const auto nan = tocd::devices::float_to_registers(std::numeric_limits<float>::quiet_NaN());
  const float before = load_limit();
  ASSERT_FLOAT_EQ(before, 50.0f);
  // 0x16: register 12 := (r AND 0) OR NaN high word.
  EXPECT_EQ(call({0x16, 0, m::hr_max_load, 0, 0, hi(nan[0]), lo(nan[0])}), exception(0x16, 1));
  // 0x17: read 1 register at 0, write NaN to 12..13.
  EXPECT_EQ(
      call({0x17, 0, 0, 0, 1, 0, m::hr_max_load, 0, 2, 4, hi(nan[0]), lo(nan[0]), hi(nan[1]), lo(nan[1])}),
      exception(0x17, 1));
  EXPECT_FLOAT_EQ(load_limit(), before);
  const Pdu others[] = {{0x01, 0, 0, 0, 1},
                        {0x02, 0, 0, 0, 1},
                        {0x05, 0, 0, 0xFF, 0},
                        {0x0F, 0, 0, 0, 1, 1, 1},
                        {0x08, 0, 0, 0, 0},
                        {0x2B, 0x0E, 1, 0},
                        {0x7F}};
  for (const Pdu& p : others) EXPECT_EQ(call(p), exception(p[0], 1)) << "function " << int(p[0]);
}

// A single-register write (0x06) to a limit register passes the same check as a 0x10 write:
// half a NaN is refused with exception 3 and nothing changes.
TEST_F(ModbusRequests, SingleRegisterWriteOfANanLimitIsRefusedLikeAMultipleWrite) {
  const auto nan = tocd::devices::float_to_registers(std::numeric_limits<float>::quiet_NaN());
  EXPECT_EQ(call({0x06, 0, m::hr_max_load, hi(nan[0]), lo(nan[0])}), exception(0x06, 3));
  EXPECT_EQ(call({0x10, 0, m::hr_max_load, 0, 2, 4, hi(nan[0]), lo(nan[0]), hi(nan[1]), lo(nan[1])}),
            exception(0x10, 3));
  const auto zero = tocd::devices::float_to_registers(0.0f);
  EXPECT_EQ(call({0x06, 0, m::hr_max_travel, hi(zero[0]), lo(zero[0])}), exception(0x06, 3));
  EXPECT_FLOAT_EQ(load_limit(), 50.0f);
}

// Limits beyond the frame's stroke (100 mm) or the load cell's capacity (500 N) are refused
// like a NaN: a limit the hardware cannot honour would be a limit in name only.
TEST_F(ModbusRequests, LimitsBeyondTheStrokeOrTheCellCapacityAreRefused) {
  const auto far = tocd::devices::float_to_registers(1e30f);
  EXPECT_EQ(call({0x10, 0, m::hr_max_travel, 0, 2, 4, hi(far[0]), lo(far[0]), hi(far[1]), lo(far[1])}),
            exception(0x10, 3));
  const auto heavy = tocd::devices::float_to_registers(501.0f);
  EXPECT_EQ(call({0x10, 0, m::hr_max_load, 0, 2, 4, hi(heavy[0]), lo(heavy[0]), hi(heavy[1]), lo(heavy[1])}),
            exception(0x10, 3));
  EXPECT_FLOAT_EQ(load_limit(), 50.0f);
  // At the capacity itself the write is taken.
  const auto full = tocd::devices::float_to_registers(500.0f);
  EXPECT_EQ(call({0x10, 0, m::hr_max_load, 0, 2, 4, hi(full[0]), lo(full[0]), hi(full[1]), lo(full[1])}),
            (Pdu{0x10, 0, m::hr_max_load, 0, 2}));
  EXPECT_FLOAT_EQ(load_limit(), 500.0f);
}

// A single-register write of the load limit's high word used to be stored but never reach the
// physics. Now a 1 N limit written with 0x06 trips when the pin presses into the sample.
TEST_F(ModbusRequests, SingleRegisterWriteOfALimitIsApplied) {
  const auto one_newton = tocd::devices::float_to_registers(1.0f);
  ASSERT_EQ(one_newton[1], 0);  // the low word already holds 0 (50.0f = 0x42480000)
  const Pdu write = {0x06, 0, m::hr_max_load, hi(one_newton[0]), lo(one_newton[0])};
  EXPECT_EQ(call(write), write);  // the echo of an accepted write
  EXPECT_FLOAT_EQ(load_limit(), 1.0f);
  // Move to 3 mm (2 mm into the 2.5 mm sample, ~10 N) at 20 mm/s: target, velocity, command.
  const auto target = tocd::devices::float_to_registers(3.0f);
  const auto velocity = tocd::devices::float_to_registers(20.0f);
  const Pdu move = {0x10,
                    0,
                    0,
                    0,
                    5,
                    10,
                    hi(target[0]),
                    lo(target[0]),
                    hi(target[1]),
                    lo(target[1]),
                    hi(velocity[0]),
                    lo(velocity[0]),
                    hi(velocity[1]),
                    lo(velocity[1]),
                    0,
                    m::cmd_move};
  EXPECT_EQ(call(move), (Pdu{0x10, 0, 0, 0, 5}));
  int fault = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (fault == 0 && std::chrono::steady_clock::now() < deadline) {
    const Pdu status = call({0x04, 0, m::in_status, 0, 2});
    if (status.size() == 6) fault = (status[4] << 8) | status[5];
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(fault, m::fault_load_limit);
  EXPECT_LT(twin_->position_mm(), 3.0 - 1e-6);  // stopped before the target
}

TEST_F(ModbusRequests, MalformedRequestsAnswerIllegalDataValueOrAddress) {
  EXPECT_EQ(call({0x10, 0, 0, 0, 2, 3, 0, 0, 0, 0}), exception(0x10, 3));  // byte count 3 for 2 registers
  EXPECT_EQ(call({0x03, 0, 0, 0, 0}), exception(0x03, 3));                 // zero registers
  EXPECT_EQ(call({0x03, 0, 0, 0, 126}), exception(0x03, 3));               // more than 125
  EXPECT_EQ(call({0x04, 0, 0}), exception(0x04, 3));                       // truncated PDU
  EXPECT_EQ(call({0x03, 0, m::holding_count, 0, 1}), exception(0x03, 2));  // outside the map
  EXPECT_EQ(call({0x06, 0, m::holding_count, 0, 1}), exception(0x06, 2));
  EXPECT_EQ(call({0x04, 0, 0, 0, m::in_poll_count}).size(), 2u + 2 * m::in_poll_count);  // still served
}

// A header that is not Modbus leaves no way to find the next frame: the connection is closed.
TEST_F(ModbusRequests, NonModbusHeaderClosesTheConnection) {
  ASSERT_TRUE(client_->send_all(std::string("\0\1\0\7\0\6\1\3\0\0\0\1", 12)));  // protocol id 7
  EXPECT_TRUE(client_->closed_by_peer(std::chrono::seconds(1)));
  RawClient zero_length(twin_->port());
  ASSERT_TRUE(zero_length.send_all(std::string("\0\1\0\0\0\0\1", 7)));
  EXPECT_TRUE(zero_length.closed_by_peer(std::chrono::seconds(1)));
  RawClient fine(twin_->port());
  EXPECT_TRUE(modbus_call(fine, {0x04, 0, 0, 0, 1}).has_value());
}

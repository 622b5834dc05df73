// The vacuum twin's Modbus RTU request handling, frame by frame on its pseudo-terminal: the
// same function codes and write checks as the tester twin.
#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include "tocd/devices/register_codec.hpp"
#include "tocd/devices/vacuum_registers.hpp"
#include "tocd/mocks/vacuum_twin.hpp"

namespace vm = tocd::devices::vacuum_map;
using Bytes = std::vector<std::uint8_t>;

namespace {

std::uint16_t crc16(const Bytes& b) {
  std::uint16_t crc = 0xFFFF;
  for (auto byte : b) {
    crc ^= byte;
    for (int i = 0; i < 8; ++i) crc = (crc & 1) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001) : crc >> 1;
  }
  return crc;
}

class VacuumRequests : public ::testing::Test {
 protected:
  void SetUp() override {
    twin_ = std::make_unique<tocd::mocks::VacuumTwin>();
    fd_ = ::open(twin_->device_path().c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
    ASSERT_GE(fd_, 0);
    termios t{};
    ::tcgetattr(fd_, &t);
    ::cfmakeraw(&t);
    ::tcsetattr(fd_, TCSANOW, &t);
  }
  void TearDown() override { ::close(fd_); }

  /// Sends slave 1 + `pdu` + CRC; returns the answer's PDU once `answer_pdu_length` bytes came.
  std::optional<Bytes> call(const Bytes& pdu, std::size_t answer_pdu_length) {
    Bytes frame{1};
    frame.insert(frame.end(), pdu.begin(), pdu.end());
    const auto crc = crc16(frame);
    frame.push_back(static_cast<std::uint8_t>(crc & 0xFF));
    frame.push_back(static_cast<std::uint8_t>(crc >> 8));
    if (::write(fd_, frame.data(), frame.size()) != static_cast<ssize_t>(frame.size())) return std::nullopt;
    Bytes got;
    const std::size_t want = 1 + answer_pdu_length + 2;
    while (got.size() < want) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, 1000) != 1) return std::nullopt;
      std::uint8_t buf[64];
      const ssize_t n = ::read(fd_, buf, sizeof buf);
      if (n <= 0) return std::nullopt;
      got.insert(got.end(), buf, buf + n);
    }
    const Bytes body(got.begin(), got.end() - 2);
    const auto crc_in = static_cast<std::uint16_t>(got[got.size() - 2] | (got[got.size() - 1] << 8));
    EXPECT_EQ(crc_in, crc16(body));
    return Bytes(got.begin() + 1, got.end() - 2);
  }

  std::unique_ptr<tocd::mocks::VacuumTwin> twin_;
  int fd_ = -1;
};

}  // namespace

TEST_F(VacuumRequests, UndocumentedFunctionCodesAnswerIllegalFunction) {
  const auto nan = tocd::devices::float_to_registers(std::numeric_limits<float>::quiet_NaN());
  const auto h = [](std::uint16_t v) { return static_cast<std::uint8_t>(v >> 8); };
  const auto l = [](std::uint16_t v) { return static_cast<std::uint8_t>(v & 0xFF); };
  EXPECT_EQ(call({0x16, 0, vm::hr_setpoint, 0, 0, h(nan[0]), l(nan[0])}, 2), (Bytes{0x96, 0x01}));
  EXPECT_EQ(
      call({0x17, 0, 0, 0, 1, 0, vm::hr_setpoint, 0, 2, 4, h(nan[0]), l(nan[0]), h(nan[1]), l(nan[1])}, 2),
      (Bytes{0x97, 0x01}));
  EXPECT_EQ(call({0x05, 0, 0, 0xFF, 0}, 2), (Bytes{0x85, 0x01}));
  // The setpoint is still the default 5 kPa, and a single-register NaN is refused with exception 3.
  const auto regs = call({0x03, 0, vm::hr_setpoint, 0, 2}, 6);
  ASSERT_TRUE(regs.has_value());
  EXPECT_FLOAT_EQ(
      tocd::devices::registers_to_float(static_cast<std::uint16_t>(((*regs)[2] << 8) | (*regs)[3]),
                                        static_cast<std::uint16_t>(((*regs)[4] << 8) | (*regs)[5])),
      5.0f);
  EXPECT_EQ(call({0x06, 0, vm::hr_setpoint, h(nan[0]), l(nan[0])}, 2), (Bytes{0x86, 0x03}));
  EXPECT_NEAR(twin_->pressure_kPa(), 101.3, 0.5);  // nothing started
}

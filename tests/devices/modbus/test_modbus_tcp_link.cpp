// Modbus TCP by host name and IPv6, a deadline on the whole answer, and identity strings
// made printable at the driver boundary.
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <netdb.h>

#include "fake_modbus_server.hpp"
#include "tocd/devices/errors.hpp"
#include "tocd/devices/tester_driver.hpp"
#include "tocd/devices/tester_registers.hpp"
#include "tocd/mocks/sim_clock.hpp"
#include "tocd/mocks/tester_twin.hpp"

namespace dev = tocd::devices;
namespace m = tocd::devices::tester_map;

namespace {

dev::ModbusOptions quick(int retries = 0) {
  dev::ModbusOptions o;
  o.timeout_s = 0.5;
  o.retries = retries;
  o.backoff_s = 0.01;
  return o;
}

// Input registers with a map version and identity strings (2 bytes per register, big end first).
std::vector<std::uint16_t> identity_registers(const std::string& vendor, const std::string& model) {
  std::vector<std::uint16_t> regs(m::input_count, 0);
  regs[m::in_map_version] = m::map_version;
  auto put = [&](int first, const std::string& s) {
    for (std::size_t i = 0; i < s.size(); ++i) {
      auto& r = regs[static_cast<std::size_t>(first) + i / 2];
      r = static_cast<std::uint16_t>(r | static_cast<std::uint8_t>(s[i]) << (i % 2 ? 0 : 8));
    }
  };
  put(m::in_identity, vendor);
  put(m::in_identity + m::identity_vendor_regs, model);
  put(m::in_identity + m::identity_vendor_regs + m::identity_model_regs, "SN1");
  put(m::in_identity + m::identity_vendor_regs + m::identity_model_regs + m::identity_serial_regs, "1.0");
  return regs;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST(ModbusTcpAddressing, SimulatedTesterByHostNameLocalhost) {
  tocd::mocks::TesterTwinOptions o;
  o.clock = std::make_shared<tocd::mocks::SimClock>(50.0);
  o.physics.tissue = tocd::mocks::make_analytic_tissue(2.5);
  tocd::mocks::TesterTwin twin(o);
  dev::ModbusTcpAddress a = twin.address();
  a.host = "localhost";
  const auto tester = dev::connect_modbus_tcp_tester(a, quick(2));
  EXPECT_FALSE(tester->identity().vendor.empty());
  EXPECT_TRUE(std::isfinite(tester->read().position_mm));
}

// libmodbus resolves with AI_ADDRCONFIG, which hides IPv6 (loopback included) on machines
// without a non-loopback IPv6 address.
bool ipv6_resolvable() {
  addrinfo hints{};
  hints.ai_flags = AI_ADDRCONFIG;
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* list = nullptr;
  const int rc = ::getaddrinfo("::1", "502", &hints, &list);
  if (list) ::freeaddrinfo(list);
  return rc == 0;
}

TEST(ModbusTcpAddressing, Ipv6Loopback) {
  if (!ipv6_resolvable()) GTEST_SKIP() << "no IPv6 address configured on this machine";
  std::unique_ptr<FakeModbusServer> server;
  try {
    server = std::make_unique<FakeModbusServer>(
        FakeModbusServer::Options{AF_INET6, {}, identity_registers("Zwick", "Z0.5")});
  } catch (const std::runtime_error&) {
    GTEST_SKIP() << "no IPv6 loopback on this machine";
  }
  const auto tester = dev::connect_modbus_tcp_tester({"::1", server->port(), 1}, quick());
  const dev::Identity id = tester->identity();
  EXPECT_EQ(id.vendor, "Zwick");
  EXPECT_EQ(id.model, "Z0.5");
}

TEST(ModbusTcpAddressing, UnresolvableHostIsNamed) {
  try {
    dev::connect_modbus_tcp_tester({"no-such-host.invalid", 1502, 1}, quick());
    FAIL() << "connected to a host that does not exist";
  } catch (const dev::ConnectionError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("mechanical tester no-such-host.invalid:1502"), std::string::npos) << msg;
    EXPECT_NE(msg.find("cannot resolve host \"no-such-host.invalid\""), std::string::npos) << msg;
  }
  EXPECT_THROW(dev::connect_modbus_tcp_tester({"", 1502, 1}, quick()), tocd::ConfigError);
}

TEST(ModbusTcpDeadline, SlowByteAnswerFailsWithinTheTimeout) {
  // 107 bytes at 90 ms each would take 9.6 s, every gap inside libmodbus's byte timeout.
  FakeModbusServer server({AF_INET, std::chrono::milliseconds(90), identity_registers("Zwick", "Z0.5")});
  const auto tester = dev::connect_modbus_tcp_tester({"127.0.0.1", server.port(), 1}, quick());
  const auto t0 = std::chrono::steady_clock::now();
  try {
    tester->identity();
    FAIL() << "a trickled answer was accepted after " << seconds_since(t0) << " s";
  } catch (const dev::TimeoutError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("mechanical tester 127.0.0.1:" + std::to_string(server.port())), std::string::npos)
        << msg;
    EXPECT_NE(msg.find("no complete answer within 500 ms"), std::string::npos) << msg;
  }
  const double took = seconds_since(t0);
  EXPECT_GE(took, 0.45);
  EXPECT_LT(took, 1.0) << "the request took " << took << " s with a 0.5 s timeout";
}

TEST(ModbusTcpDeadline, RetriesEachGetOneTimeoutAndTheLinkRecovers) {
  FakeModbusServer slow({AF_INET, std::chrono::milliseconds(90), identity_registers("Zwick", "Z0.5")});
  const auto tester = dev::connect_modbus_tcp_tester({"127.0.0.1", slow.port(), 1}, quick(1));
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_THROW(tester->identity(), dev::TimeoutError);
  EXPECT_LT(seconds_since(t0), 1.6);  // two attempts of 0.5 s and a 10 ms backoff
}

TEST(ModbusTcpDeadline, PromptAnswersAreUnaffected) {
  FakeModbusServer server({AF_INET, {}, identity_registers("Zwick", "Z0.5")});
  const auto tester = dev::connect_modbus_tcp_tester({"127.0.0.1", server.port(), 1}, quick());
  for (int i = 0; i < 50; ++i) EXPECT_EQ(tester->identity().vendor, "Zwick");
}

TEST(InstrumentStrings, IdentityIsMadePrintable) {
  const std::string fffd = "\xEF\xBF\xBD";
  FakeModbusServer server({AF_INET, {}, identity_registers("Evil\x1B[2J", "M\xFF\x01x")});
  const auto tester = dev::connect_modbus_tcp_tester({"127.0.0.1", server.port(), 1}, quick());
  const dev::Identity id = tester->identity();
  EXPECT_EQ(id.vendor, "Evil" + fffd + "[2J");
  EXPECT_EQ(id.model, "M" + fffd + fffd + "x");
  EXPECT_EQ(id.serial, "SN1");
}

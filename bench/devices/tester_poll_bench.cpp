// Sustained polling of tester position + load (one Modbus transaction per reading) over
// loopback TCP against the tester twin. Usage: tester_poll_bench [seconds] (default 2).
#include <algorithm>
#include <cstdlib>
#include <vector>

#include <fmt/format.h>

#include "tocd/core/clock.hpp"
#include "tocd/devices/tester_driver.hpp"
#include "tocd/mocks/tester_twin.hpp"

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 2.0;
  tocd::mocks::TesterTwin twin;
  auto tester = tocd::devices::connect_modbus_tcp_tester(twin.address());
  tester->move_to(3.0, 0.5);                     // the twin integrates motion and load on every request
  for (int i = 0; i < 200; ++i) tester->read();  // warm up
  std::vector<double> latency_us;
  latency_us.reserve(static_cast<std::size_t>(seconds * 20000));
  const auto start = tocd::monotonic_ns();
  const auto end = start + static_cast<std::int64_t>(seconds * 1e9);
  auto now = start;
  while (now < end) {
    const auto t0 = now;
    tester->read();
    now = tocd::monotonic_ns();
    latency_us.push_back(static_cast<double>(now - t0) * 1e-3);
  }
  const double elapsed = static_cast<double>(now - start) * 1e-9;
  std::sort(latency_us.begin(), latency_us.end());
  auto pct = [&](double p) { return latency_us[static_cast<std::size_t>(p * (latency_us.size() - 1))]; };
  const double rate = static_cast<double>(latency_us.size()) / elapsed;
  fmt::print("tester position+load polling, Modbus TCP loopback, {:.1f} s\n", elapsed);
  fmt::print("  readings      {}\n  rate          {:.0f} /s (target >= 1000 /s: {})\n", latency_us.size(),
             rate, rate >= 1000.0 ? "met" : "NOT met");
  fmt::print("  latency us    p50 {:.1f}  p95 {:.1f}  p99 {:.1f}  max {:.1f}\n", pct(0.50), pct(0.95),
             pct(0.99), latency_us.back());
  return rate >= 1000.0 ? 0 : 1;
}

// The simulated mechanical tester's Modbus TCP server: the input is what one client sends on
// one connection (MBAP frames back to back), served by the server's own framing and request
// handling. Whatever arrives, every answer must be a well-formed Modbus TCP frame. Each input
// gets a fresh tester, so that a finding replays from its input alone; its clock runs at the
// largest factor `tocdlab simlab --clock-factor` accepts, so moves finish within one input.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "fuzz_support.hpp"
#include "tocd/mocks/sim_clock.hpp"
#include "tocd/mocks/tester_twin.hpp"

namespace {

tocd::mocks::TesterTwinOptions options() {
  tocd::mocks::TesterTwinOptions o;
  o.clock = std::make_shared<tocd::mocks::SimClock>(1e6);
  return o;
}

// Each answer frame: MBAP header whose length field covers exactly the unit id and the PDU.
void check_frames(const std::string& sent) {
  std::size_t at = 0;
  while (at < sent.size()) {
    if (sent.size() - at < 8) std::abort();
    const auto* p = reinterpret_cast<const unsigned char*>(sent.data() + at);
    const std::size_t length = (p[4] << 8) | p[5];
    if (p[2] != 0 || p[3] != 0 || length < 2 || length > 254 || sent.size() - at < 6 + length) std::abort();
    at += 6 + length;
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tocd::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tocd::mocks::TesterTwin tester(options());
  const auto reply = tester.serve_stream(tocd::fuzz::as_text(data, size));
  check_frames(reply.sent);
  return 0;
}

// The simulated vacuum controller's Modbus RTU request handling. The input is one frame as it
// would arrive on the serial line; it is served twice: as it is (so bad CRCs, short frames and
// other slaves' ids are exercised) and with its last two bytes replaced by the right CRC (so
// that the fuzzer reaches the request decoding, which a random CRC would almost never pass).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "fuzz_support.hpp"
#include "tocd/mocks/sim_clock.hpp"
#include "tocd/mocks/vacuum_twin.hpp"

namespace {

tocd::mocks::VacuumTwin& vacuum() {
  static tocd::mocks::VacuumTwin twin([] {
    tocd::mocks::VacuumTwinOptions o;
    o.clock = std::make_shared<tocd::mocks::SimClock>(1000.0);
    return o;
  }());
  return twin;
}

// CRC-16/MODBUS (polynomial 0xA001 reflected, initial 0xFFFF), written here from the Modbus
// over serial line specification so that the check does not lean on the code under test.
std::uint16_t crc16(const std::uint8_t* p, std::size_t n) {
  std::uint16_t crc = 0xFFFF;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= p[i];
    for (int b = 0; b < 8; ++b) crc = (crc & 1) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001) : crc >> 1;
  }
  return crc;
}

// An answer is silence or one frame to our slave id with a correct CRC.
void check_answer(const std::vector<std::uint8_t>& a) {
  if (a.empty()) return;
  if (a.size() < 5 || a[0] != 1) std::abort();
  const std::uint16_t crc = crc16(a.data(), a.size() - 2);
  if (a[a.size() - 2] != (crc & 0xFF) || a[a.size() - 1] != (crc >> 8)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tocd::fuzz::quiet_logging();
  (void)vacuum();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  check_answer(vacuum().serve_frame(std::span(data, size)));
  if (size < 4) return 0;
  std::vector<std::uint8_t> frame(data, data + size);
  const std::uint16_t crc = crc16(frame.data(), size - 2);
  frame[size - 2] = static_cast<std::uint8_t>(crc & 0xFF);
  frame[size - 1] = static_cast<std::uint8_t>(crc >> 8);
  check_answer(vacuum().serve_frame(frame));
  return 0;
}

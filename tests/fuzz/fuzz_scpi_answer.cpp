// What an SCPI instrument answers, as the drivers decode it: numbers (strict <NRf>), error
// queue entries, and identity text made printable before it is stored or shown.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "fuzz_support.hpp"
#include "tocd/core/printable.hpp"
#include "tocd/devices/errors.hpp"
#include "tocd/devices/scpi_client.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tocd::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto answer = tocd::fuzz::as_text(data, size);
  try {
    const double v = tocd::devices::parse_scpi_number(answer, "fuzz meter", "MEAS:POW?");
    (void)v;
  } catch (const tocd::devices::ProtocolError&) {
  }
  try {
    (void)tocd::devices::parse_scpi_error(answer, "fuzz meter");
  } catch (const tocd::devices::ProtocolError&) {
  }
  const std::string shown = tocd::printable_text(answer);
  // Printable means: no C0 control character, no DEL, and no C1 (U+0080..U+009F, which
  // UTF-8 writes as 0xC2 0x80..0x9F) survives.
  for (std::size_t i = 0; i < shown.size(); ++i) {
    const auto c = static_cast<unsigned char>(shown[i]);
    if (c < 0x20 || c == 0x7F) std::abort();
    if (c == 0xC2 && i + 1 < shown.size() && static_cast<unsigned char>(shown[i + 1]) <= 0x9F) std::abort();
  }
  return 0;
}

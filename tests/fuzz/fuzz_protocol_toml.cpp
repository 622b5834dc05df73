// The protocol TOML (`tocdlab run --protocol`): parse_protocol, then what the run engine asks
// of a protocol before it starts (its duration estimate).
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "tocd/acquisition/protocol.hpp"
#include "tocd/core/error.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tocd::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto protocol = tocd::acquisition::parse_protocol(tocd::fuzz::as_text(data, size), "fuzz.toml");
    (void)protocol.nominal_duration_s();
  } catch (const tocd::Error&) {
  }
  return 0;
}

// The optics TOML (`tocdlab mc --optics`): parse_optics_toml checks every region and key.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/mc/optics.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tocd::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)tocd::sim::mc::parse_optics_toml(std::string(tocd::fuzz::as_text(data, size)), "fuzz.toml");
  } catch (const tocd::Error&) {
  }
  return 0;
}

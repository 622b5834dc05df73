// The lab config TOML (`--lab`). A config that parses must also survive the way back:
// to_toml writes it and parse_lab_config reads that again (the GUI saves configs this way).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "fuzz_support.hpp"
#include "tocd/core/error.hpp"
#include "tocd/devices/lab.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tocd::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tocd::devices::LabConfig cfg;
  try {
    cfg = tocd::devices::parse_lab_config(tocd::fuzz::as_text(data, size), "fuzz.toml");
  } catch (const tocd::Error&) {
    return 0;
  }
  const std::string written = tocd::devices::to_toml(cfg);
  const auto again = tocd::devices::parse_lab_config(written, "written.toml");  // throws: a finding
  if (tocd::devices::to_toml(again) != written) std::abort();  // the round trip lost something
  return 0;
}

// TetGen .node/.ele/.face files as `tocdlab mc --mesh PREFIX` reads them: read_tetgen, then
// mc::prepare (the checks and point-location grid every Monte Carlo run builds).
// Input: the .node text, then optionally "\n@@\n" and the .ele text, then optionally
// "\n@@\n" and the .face text (no .face file when that part is absent).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/mc/prepared_mesh.hpp"
#include "tocd/sim/mesh/tetgen_io.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tocd::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  std::string_view rest = tocd::fuzz::as_text(data, size);
  constexpr std::string_view separator = "\n@@\n";
  std::string_view parts[3];
  int n = 0;
  for (; n < 3; ++n) {
    const auto at = n < 2 ? rest.find(separator) : std::string_view::npos;
    parts[n] = rest.substr(0, at);
    if (at == std::string_view::npos) {
      ++n;
      break;
    }
    rest.remove_prefix(at + separator.size());
  }
  const fs::path prefix = tocd::fuzz::scratch_dir() / "mesh";
  tocd::fuzz::write_file(fs::path(prefix).concat(".node"), parts[0]);
  tocd::fuzz::write_file(fs::path(prefix).concat(".ele"), parts[1]);
  std::error_code ec;
  if (n == 3)
    tocd::fuzz::write_file(fs::path(prefix).concat(".face"), parts[2]);
  else
    fs::remove(fs::path(prefix).concat(".face"), ec);
  try {
    (void)tocd::sim::mc::prepare(tocd::sim::mesh::read_tetgen(prefix));
  } catch (const tocd::Error&) {
    // refused with a message: what a bad mesh file should get
  }
  return 0;
}

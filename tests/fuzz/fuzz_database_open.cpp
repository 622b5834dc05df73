// Opening arbitrary bytes as a measurement database, as `tocdlab runs FILE` does: the bytes
// become a file, db::Reader opens it (identity, schema version, quick_check) and lists the
// runs; for a file that opens, each listed run is read the way `compare` and `export` read it.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz_support.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/reader.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tocd::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  const fs::path file = tocd::fuzz::scratch_dir() / "fuzz.sqlite";
  std::error_code ec;
  for (const char* suffix : {"-wal", "-shm", "-journal"}) fs::remove(fs::path(file).concat(suffix), ec);
  tocd::fuzz::write_file(file, tocd::fuzz::as_text(data, size));
  try {
    const tocd::db::Reader reader(file);
    int read = 0;
    for (const auto& summary : reader.runs()) {
      if (++read > 4) break;  // a few runs are enough to reach every query
      const std::int64_t id = summary.run.id;
      (void)reader.shown_status(id);
      (void)reader.compare(id);
      (void)reader.events(id);
      for (const auto& channel : reader.channels(id)) {
        tocd::db::SampleQuery q;
        q.decimation = tocd::db::Decimation::min_max;
        q.max_points = 16;
        (void)reader.samples(channel.id, q);
      }
    }
  } catch (const tocd::Error&) {
  }
  return 0;
}

// Records the demo protocol on the default simulated sample (read from the sample cache, or
// prepared once), then identifies its sample as `tocdlab identify` does and prints how long
// each part took. Usage: identify_bench [photons per held step] [Monte Carlo threads]
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <thread>

#include <fmt/format.h>
#include <unistd.h>

#include "tocd/acquisition/lab_session.hpp"
#include "tocd/analysis/identify_sample.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/mocks/default_sample.hpp"
#include "tocd/mocks/sample_truth.hpp"
#include "tocd/mocks/sim_tissue_cache.hpp"
#include "tocd/mocks/simulated_lab.hpp"
#include "tocd/test/simulated_run.hpp"

namespace acq = tocd::acquisition;
namespace mocks = tocd::mocks;

int main(int argc, char** argv) {
  const std::uint64_t photons = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 50000;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 0;
  const auto db_path =
      std::filesystem::temp_directory_path() / fmt::format("identify_bench_{}.db", ::getpid());
  std::int64_t run = 0;
  {
    const acq::Protocol protocol = acq::demo_protocol();
    mocks::DefaultSampleOptions so;
    so.cache_dir = mocks::default_sim_tissue_cache_dir();
    mocks::SimulatedLabOptions lo = mocks::simulated_lab_options(mocks::SampleTruth{});
    lo.tissue = mocks::make_default_sample(protocol.sample.thickness_mm, 1.5, so);
    lo.clock_factor = 5;
    mocks::SimulatedLab lab(lo);
    const auto recorded = tocd::test::record_on_simulated_lab(db_path, lab, lo.clock_factor, protocol);
    if (recorded.end != acq::EngineState::completed) {
      std::cerr << "identify_bench: the demo run did not complete\n";
      return 1;
    }
    run = recorded.id;
  }
  tocd::analysis::SampleIdentificationOptions io;
  io.monte_carlo.photons = photons;
  io.monte_carlo.threads = threads;
  const auto t0 = std::chrono::steady_clock::now();
  const auto id = tocd::analysis::identify_sample(tocd::db::Reader(db_path), run, io);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << fmt::format(
      "identify the demo run: {:.1f} s in all (mechanics: FE {:.1f} s + fit {:.1f} s; optics: {:.1f} s, {} "
      "Monte "
      "Carlo runs at {} photons), {} hardware threads\n",
      total, id.mechanics.fe_seconds, id.mechanics.fit_seconds, id.optics ? id.optics->seconds : 0.0,
      id.optics ? id.optics->monte_carlo_runs : 0, photons, std::thread::hardware_concurrency());
  for (const char* ext : {"", "-wal", "-shm", "-runlock"}) std::filesystem::remove(db_path.string() + ext);
  return 0;
}

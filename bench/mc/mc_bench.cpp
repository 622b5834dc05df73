// Prints photons/s and scattering events/s for the two benchmark problems of the photon
// Monte Carlo, with 1 thread and with 2 (or --threads N), after a warm-up run; the skin slab
// also with the transmittance derivatives on (RunSettings::transmittance_derivatives).
//   mc_bench [--photons N] [--threads N] [--cells N]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <fmt/format.h>
#include <time.h>

#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/mesh/slab_mesh.hpp"

namespace mc = tocd::sim::mc;
namespace msh = tocd::sim::mesh;

namespace {

constexpr std::int32_t kSkin = 1, kGlass = 2, kAir = 3;

mc::Optics optics() {
  mc::Optics o;
  o.regions[kSkin] = {0.089, 28.9, 0.926, 1.38, "skin"};
  o.regions[kGlass] = {0.001, 0.001, 1.0, 1.458, "glass"};
  o.regions[kAir] = {0.001, 0.001, 1.0, 1.003, "air"};
  return o;
}

// Cells about cubic, as a mesher would make them: `cells` across 10 mm, so a layer of
// thickness t gets round(cells * t / 10) cells in z.
int z_cells(int cells, double thickness_mm) {
  return std::max(1, static_cast<int>(cells * thickness_mm / 10.0 + 0.5));
}

// 10 x 10 x 2.5 mm skin; 6 tets per cell (cells = 32: 49,152 tets).
msh::SlabSpec skin_slab(int cells) {
  msh::SlabSpec s;
  s.width_mm = s.depth_mm = 10.0;
  s.cells_x = s.cells_y = cells;
  s.layers = {{2.5, kSkin, z_cells(cells, 2.5)}};
  return s;
}

// The same skin between 1 mm of air above and a 1 mm glass slide below.
msh::SlabSpec layered_slab(int cells) {
  msh::SlabSpec s = skin_slab(cells);
  s.layers = {{1.0, kAir, z_cells(cells, 1.0)},
              {2.5, kSkin, z_cells(cells, 2.5)},
              {1.0, kGlass, z_cells(cells, 1.0)}};
  return s;
}

void bench(const char* name, const msh::SlabSpec& spec, std::uint64_t photons, int threads,
           bool derivatives = false) {
  const mc::PreparedMesh mesh = mc::prepare(msh::make_slab(spec));
  mc::Source beam;  // pencil straight down onto the centre, off the central node
  beam.origin = {0.0123, -0.0217, 10.0};
  mc::RunSettings s;
  s.photons = photons / 10;
  s.threads = threads;
  s.batches = 20;
  s.tally_per_tet = std::getenv("MC_NO_TET_TALLY") == nullptr;
  s.transmittance_derivatives = derivatives;
  mc::run(mesh, optics(), beam, s);  // warm-up: page in the mesh, settle the clocks
  s.photons = photons;
  // CPU time as well as wall time: photons per CPU-second stays comparable on a busy machine.
  timespec c0{}, c1{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
  const mc::Result r = mc::run(mesh, optics(), beam, s);
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
  const double cpu_s =
      static_cast<double>(c1.tv_sec - c0.tv_sec) + 1e-9 * static_cast<double>(c1.tv_nsec - c0.tv_nsec);
  std::printf(
      "%-28s tets %7zu threads %d photons %9llu  %8.0f photons/s  %6.2f Mevents/s  %5.1f events/photon %5.1f "
      "faces/photon  "
      "T %.5f R %.5f side %.5f  (%.2f s, %.0f photons per CPU-second)\n",
      name, mesh.tets.size(), threads, static_cast<unsigned long long>(r.photons), r.photons_per_second,
      r.events_per_second * 1e-6, static_cast<double>(r.events) / static_cast<double>(r.photons),
      static_cast<double>(r.face_hits) / static_cast<double>(r.photons), r.transmittance.mean,
      r.reflectance.mean, r.side_loss.mean, r.seconds, static_cast<double>(r.photons) / cpu_s);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t photons = 1'000'000;
  int max_threads = 2, cells = 32;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--photons"))
      photons = std::strtoull(argv[i + 1], nullptr, 10);
    else if (!std::strcmp(argv[i], "--threads"))
      max_threads = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--cells"))
      cells = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: mc_bench [--photons N] [--threads N] [--cells N]\n");
      return 2;
    }
  }
  for (int threads : {1, max_threads}) {
    bench("(a) skin slab", skin_slab(cells), photons, threads);
    bench("(a) skin slab, dT/dmu", skin_slab(cells), photons, threads, true);
    bench("(b) air / skin / glass", layered_slab(cells), photons, threads);
  }
  return 0;
}

// Prints photons/s and scattering events/s for the two benchmark problems of the photon
// Monte Carlo, with 1 thread and with 2 (or --threads N), after a warm-up run; the skin slab
// also with the transmittance derivatives on (RunSettings::transmittance_derivatives).
//   mc_bench [--photons N] [--threads N] [--cells N]
#include <cstdio>
#include <cstdlib>
#include <string>

#include <fmt/format.h>
#include <time.h>

#include "slab_problems.hpp"
#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/mesh/slab_mesh.hpp"

namespace mc = tocd::sim::mc;
namespace msh = tocd::sim::mesh;

namespace {

using tocd::bench::layered_slab;
using tocd::bench::skin_slab;
using tocd::bench::slab_optics;

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
  mc::run(mesh, slab_optics(), beam, s);  // warm-up: page in the mesh, settle the clocks
  s.photons = photons;
  // CPU time as well as wall time: photons per CPU-second stays comparable on a busy machine.
  timespec c0{}, c1{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
  const mc::Result r = mc::run(mesh, slab_optics(), beam, s);
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
  tocd::bench::SlabBenchOptions o;
  o.threads = 2;  // the most threads: each problem runs with 1 and with this many
  if (const auto stop = tocd::bench::parse_slab_bench_options(argc, argv, "mc_bench", o)) return *stop;
  for (int threads : {1, o.threads}) {
    bench("(a) skin slab", skin_slab(o.cells), o.photons, threads);
    bench("(a) skin slab, dT/dmu", skin_slab(o.cells), o.photons, threads, true);
    bench("(b) air / skin / glass", layered_slab(o.cells), o.photons, threads);
  }
  return 0;
}

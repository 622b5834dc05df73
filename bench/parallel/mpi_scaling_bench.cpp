// Strong scaling of the photon Monte Carlo across MPI ranks, and the cost of its reduction.
// Run it under mpirun with 1 and with 2 (or more) ranks: `bench/parallel/strong_scaling.sh`
// does both and prints the parallel efficiency. Each run prints, from rank 0:
//   - the wall time of the whole run (mc::run, tallies summed over the ranks) and photons/s;
//   - the parts: this rank's batches, the sum of the tallies (MPI_Allreduce of exact
//     fixed-point words: time and bytes), and the finish;
//   - the sum alone for a tally the size of a 0.5 M-tet mesh (the paper's meshes), for the
//     scaling model in docs/cluster.md.
//   mpi_scaling_bench [--photons N] [--threads N] [--cells N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "slab_problems.hpp"
#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/mesh/slab_mesh.hpp"
#include "tocd/sim/parallel/team.hpp"

namespace mc = tocd::sim::mc;
namespace msh = tocd::sim::mesh;

namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

using tocd::bench::layered_slab;
using tocd::bench::slab_optics;

int main(int argc, char** argv) {
  tocd::bench::SlabBenchOptions o;
  if (const auto stop = tocd::bench::parse_slab_bench_options(argc, argv, "mpi_scaling_bench", o))
    return *stop;
  const std::uint64_t photons = o.photons;
  const int threads = o.threads;
  auto& team = tocd::sim::parallel::world();
  const bool root = team.rank() == 0;
  // The air / skin / glass slab of mc_bench (b): 10 x 10 mm, 1 + 2.5 + 1 mm.
  const mc::PreparedMesh mesh = mc::prepare(msh::make_slab(layered_slab(o.cells)));
  mc::Source beam;
  beam.origin = {0.0123, -0.0217, 10.0};
  mc::RunSettings s;
  s.photons = photons;
  s.threads = threads;
  s.batches = 20;
  s.tally_per_tet = true;  // per-tet fluence: the reduction carries the whole mesh
  s.team = &team;

  s.photons = photons / 20;
  mc::run(mesh, slab_optics(), beam, s);  // warm-up
  s.photons = photons;
  const mc::Result r = mc::run(mesh, slab_optics(), beam, s);

  // The same run in its parts, timed apart.
  const int b0 = s.batches * team.rank() / team.size(), b1 = s.batches * (team.rank() + 1) / team.size();
  double t = now_s();
  mc::Tallies tallies = mc::run_batches(mesh, slab_optics(), beam, s, b0, b1);
  const double compute_s = now_s() - t;
  std::int64_t one = 1;
  team.sum(std::span(&one, 1));  // line up the ranks so the sum times the sum, not the wait
  t = now_s();
  team.sum(tallies.words);
  const double sum_s = now_s() - t;
  t = now_s();
  const mc::Result parts = mc::finish(mesh, slab_optics(), s, tallies);
  const double finish_s = now_s() - t;

  // The sum alone for a 0.5 M-tet mesh's tallies.
  const std::size_t paper_words = tallies.words.size() / std::max<std::size_t>(1, mesh.tets.size()) * 500'000;
  std::vector<std::int64_t> big(paper_words, 1);
  team.sum(std::span(&one, 1));
  t = now_s();
  team.sum(big);
  const double big_sum_s = now_s() - t;

  if (root) {
    std::printf("ranks %d threads %d tets %zu photons %llu  wall %.3f s  %.0f photons/s  T %.6f +- %.6f\n",
                team.size(), threads, mesh.tets.size(), static_cast<unsigned long long>(r.photons), r.seconds,
                r.photons_per_second, r.transmittance.mean, r.transmittance.se);
    std::printf("parts: batches %d-%d of rank 0 %.3f s, sum of %zu words (%.1f MB) %.4f s, finish %.4f s%s\n",
                b0, b1, compute_s, tallies.words.size(), 8e-6 * static_cast<double>(tallies.words.size()),
                sum_s, finish_s,
                parts.transmittance.mean == r.transmittance.mean ? "" : "  (parts differ from the run!)");
    std::printf("sum of a 0.5 M-tet tally: %zu words (%.1f MB) %.4f s\n", paper_words,
                8e-6 * static_cast<double>(paper_words), big_sum_s);
  }
  tocd::sim::parallel::finish_world();
  return parts.transmittance.mean == r.transmittance.mean ? 0 : 1;
}

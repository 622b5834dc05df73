#pragma once
// The slab problems of the Monte Carlo benchmarks and their common options, shared by
// mc_bench and mpi_scaling_bench so that their figures are of the same problem.
//   [--photons N] [--threads N] [--cells N]
#include <cstdint>
#include <optional>

#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/mesh/slab_mesh.hpp"

namespace tocd::bench {

constexpr std::int32_t kSkin = 1, kGlass = 2, kAir = 3;

sim::mc::Optics slab_optics();

// 10 x 10 x 2.5 mm skin; 6 tets per cell (cells = 32: 49,152 tets).
sim::mesh::SlabSpec skin_slab(int cells);

// The same skin between 1 mm of air above and a 1 mm glass slide below.
sim::mesh::SlabSpec layered_slab(int cells);

struct SlabBenchOptions {
  std::uint64_t photons = 1'000'000;
  int threads = 1;
  int cells = 32;
};

/// Reads the options into `o`, whose values stand where an option is not given. Returns the
/// exit code when the program is to stop here: 0 after `--help`, non-zero (the error printed)
/// for an option it does not know or a value out of range.
std::optional<int> parse_slab_bench_options(int argc, char** argv, const char* program, SlabBenchOptions& o);

}  // namespace tocd::bench

#include "slab_problems.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace tocd::bench {

namespace {

// Cells about cubic, as a mesher would make them: `cells` across 10 mm, so a layer of
// thickness t gets round(cells * t / 10) cells in z.
int z_cells(int cells, double thickness_mm) {
  return std::max(1, static_cast<int>(cells * thickness_mm / 10.0 + 0.5));
}

}  // namespace

sim::mc::Optics slab_optics() {
  sim::mc::Optics o;
  o.regions[kSkin] = {0.089, 28.9, 0.926, 1.38, "skin"};
  o.regions[kGlass] = {0.001, 0.001, 1.0, 1.458, "glass"};
  o.regions[kAir] = {0.001, 0.001, 1.0, 1.003, "air"};
  return o;
}

sim::mesh::SlabSpec skin_slab(int cells) {
  sim::mesh::SlabSpec s;
  s.width_mm = s.depth_mm = 10.0;
  s.cells_x = s.cells_y = cells;
  s.layers = {{2.5, kSkin, z_cells(cells, 2.5)}};
  return s;
}

sim::mesh::SlabSpec layered_slab(int cells) {
  sim::mesh::SlabSpec s = skin_slab(cells);
  s.layers = {{1.0, kAir, z_cells(cells, 1.0)},
              {2.5, kSkin, z_cells(cells, 2.5)},
              {1.0, kGlass, z_cells(cells, 1.0)}};
  return s;
}

bool parse_slab_bench_options(int argc, char** argv, const char* program, SlabBenchOptions& o) {
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--photons"))
      o.photons = std::strtoull(argv[i + 1], nullptr, 10);
    else if (!std::strcmp(argv[i], "--threads"))
      o.threads = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--cells"))
      o.cells = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: %s [--photons N] [--threads N] [--cells N]\n", program);
      return false;
    }
  }
  return true;
}

}  // namespace tocd::bench

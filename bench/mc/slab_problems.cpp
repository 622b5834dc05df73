#include "slab_problems.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <CLI/CLI.hpp>

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

std::optional<int> parse_slab_bench_options(int argc, char** argv, const char* program, SlabBenchOptions& o) {
  CLI::App app{"Photons/s of the tet-mesh Monte Carlo on the skin slab problems", program};
  app.add_option("--photons", o.photons, "photons per problem")->check(CLI::PositiveNumber);
  app.add_option("--threads", o.threads, "Monte Carlo threads")->check(CLI::PositiveNumber);
  app.add_option("--cells", o.cells, "cells across the slab's 10 mm")->check(CLI::PositiveNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return std::nullopt;
}

}  // namespace tocd::bench

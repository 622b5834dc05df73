#pragma once
// Helpers shared by the Monte Carlo tests: slabs, optics and runs in one call.

#include <cmath>
#include <cstdint>
#include <numbers>

#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/mesh/slab_mesh.hpp"

namespace tocd::sim::mc::testing {

inline RegionOptics props(double mu_a, double mu_s, double g, double n) {
  return {mu_a, mu_s, g, n, ""};
}

/// One-region slab, `width` wide, `cells_xy` cells across and `cells_z` through.
inline PreparedMesh slab(double width_mm, double thickness_mm, int cells_xy = 4, int cells_z = 2,
                         double rotation_deg = 0.0) {
  mesh::SlabSpec spec;
  spec.width_mm = spec.depth_mm = width_mm;
  spec.cells_x = spec.cells_y = cells_xy;
  spec.layers = {{thickness_mm, 1, cells_z}};
  spec.rotation_deg = rotation_deg;
  spec.rotation_axis = {1.0, 2.0, 0.5};
  return prepare(mesh::make_slab(spec));
}

/// Pencil beam down onto the slab top, entering at (x, y) and tilted by `polar_deg` from -z
/// in the x-z plane. Offsets avoid starting exactly on a mesh node.
inline Source pencil(double polar_deg = 0.0, double x = 0.0123, double y = -0.0217, double top_z = 0.0) {
  Source s;
  const double th = polar_deg * std::numbers::pi / 180.0;
  s.direction = {std::sin(th), 0.0, -std::cos(th)};
  s.origin = {x, y, top_z};
  return s;
}

inline RunSettings settings(std::uint64_t photons, std::uint64_t seed = 7, int threads = 2) {
  RunSettings s;
  s.photons = photons;
  s.seed = seed;
  s.threads = threads;
  s.batches = 20;
  return s;
}

inline Optics one_region(const RegionOptics& r) {
  Optics o;
  o.regions[1] = r;
  return o;
}

/// Suite names get a "Long" suffix in the physics-long build so ctest names stay unique.
#ifdef TOCD_MC_LONG
#define MC_SUITE(name) name##Long
#else
#define MC_SUITE(name) name
#endif

/// Photon count scale: physics-long builds define TOCD_MC_LONG to run 20x more photons.
#ifdef TOCD_MC_LONG
inline constexpr std::uint64_t kScale = 20;
#else
inline constexpr std::uint64_t kScale = 1;
#endif

}  // namespace tocd::sim::mc::testing

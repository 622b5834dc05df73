// The mesh must not change the physics: a coarse and a fine tetrahedralisation of the same
// slab, and the slab rotated in space, give the same tallies; the thread count never changes
// them; energy is conserved to round-off.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "slab_fixture.hpp"

namespace mc = tocd::sim::mc;
using namespace tocd::sim::mc::testing;

namespace {

// Index-mismatched scattering slab: exercises Fresnel at the outer faces, scattering and
// roulette. 1 mm thick, 20 mm wide (side loss < 1e-4).
const mc::Optics kTissue = one_region(props(0.1, 10.0, 0.9, 1.4));

void expect_same(const mc::Estimate& a, const mc::Estimate& b, const char* what) {
  // Independent seeds: the difference has standard error sqrt(se_a^2 + se_b^2); 4 of them.
  EXPECT_NEAR(a.mean, b.mean, 4.0 * std::hypot(a.se, b.se)) << what;
}

std::array<double, 3> rotate(std::array<double, 3> v, std::array<double, 3> axis, double deg,
                             std::array<double, 3> centre) {
  const double len = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (auto& a : axis) a /= len;
  for (int k = 0; k < 3; ++k) v[k] -= centre[k];
  const double th = deg * std::numbers::pi / 180.0, c = std::cos(th), s = std::sin(th);
  const double kd = axis[0] * v[0] + axis[1] * v[1] + axis[2] * v[2];
  const std::array<double, 3> kx{axis[1] * v[2] - axis[2] * v[1], axis[2] * v[0] - axis[0] * v[2],
                                 axis[0] * v[1] - axis[1] * v[0]};
  std::array<double, 3> out;
  for (int k = 0; k < 3; ++k) out[k] = centre[k] + v[k] * c + kx[k] * s + axis[k] * kd * (1.0 - c);
  return out;
}

}  // namespace

TEST(MC_SUITE(McInvariance), CoarseAndFineMeshesAgree) {
  const mc::Result coarse = mc::run(slab(20.0, 1.0, 2, 1), kTissue, pencil(0.0, 0.0123, -0.0217, 1.0),
                                    settings(200000 * kScale, 11));
  const mc::Result fine = mc::run(slab(20.0, 1.0, 24, 10), kTissue, pencil(0.0, 0.0123, -0.0217, 1.0),
                                  settings(200000 * kScale, 12));
  expect_same(coarse.transmittance, fine.transmittance, "T");
  expect_same(coarse.reflectance, fine.reflectance, "R");
  expect_same(coarse.absorbed, fine.absorbed, "A");
  std::printf("coarse (%zu tets) T %.5f R %.5f | fine (%zu tets) T %.5f R %.5f (se %.5f)\n",
              slab(20.0, 1.0, 2, 1).tets.size(), coarse.transmittance.mean, coarse.reflectance.mean,
              slab(20.0, 1.0, 24, 10).tets.size(), fine.transmittance.mean, fine.reflectance.mean,
              fine.transmittance.se);
}

TEST(MC_SUITE(McInvariance), RotatedSlabAgrees) {
  // make_slab rotates about (0, 0, thickness/2); the beam is rotated with it. Rotated, the
  // top and bottom are no longer the box's, so compare the slab's own face markers.
  constexpr double kDeg = 37.0;
  const std::array<double, 3> axis{1.0, 2.0, 0.5}, centre{0.0, 0.0, 0.5};
  mc::Source beam = pencil(0.0, 0.0123, -0.0217, 1.0);
  beam.origin = rotate(beam.origin, axis, kDeg, centre);
  beam.direction = rotate(beam.direction, axis, kDeg, {0.0, 0.0, 0.0});
  const mc::Result turned =
      mc::run(slab(20.0, 1.0, 6, 3, kDeg), kTissue, beam, settings(200000 * kScale, 21));
  const mc::Result flat = mc::run(slab(20.0, 1.0, 6, 3), kTissue, pencil(0.0, 0.0123, -0.0217, 1.0),
                                  settings(200000 * kScale, 22));
  using tocd::sim::mesh::kSlabBottomMarker;
  using tocd::sim::mesh::kSlabTopMarker;
  expect_same(turned.exit_by_marker.at(kSlabBottomMarker), flat.transmittance, "T");
  expect_same(turned.exit_by_marker.at(kSlabTopMarker), flat.reflectance, "R");
  expect_same(turned.absorbed, flat.absorbed, "A");
  EXPECT_NEAR(turned.specular.mean, flat.specular.mean, 1e-12);
  EXPECT_NEAR(flat.exit_by_marker.at(kSlabBottomMarker).mean, flat.transmittance.mean, 1e-15);
}

TEST(MC_SUITE(McReproducibility), ThreadCountNeverChangesTallies) {
  const mc::PreparedMesh mesh = slab(20.0, 1.0, 6, 3);
  mc::Result r[3];
  for (int t = 1; t <= 3; ++t)
    r[t - 1] = mc::run(mesh, kTissue, pencil(0.0, 0.0123, -0.0217, 1.0), settings(20000, 5, t));
  for (int i = 1; i < 3; ++i) {
    // Bitwise: per-photon streams and batch-ordered reduction.
    EXPECT_EQ(r[i].transmittance.mean, r[0].transmittance.mean);
    EXPECT_EQ(r[i].transmittance.se, r[0].transmittance.se);
    EXPECT_EQ(r[i].reflectance.mean, r[0].reflectance.mean);
    EXPECT_EQ(r[i].events, r[0].events);
    EXPECT_EQ(r[i].absorbed_per_tet, r[0].absorbed_per_tet);
  }
  const mc::Result other = mc::run(mesh, kTissue, pencil(0.0, 0.0123, -0.0217, 1.0), settings(20000, 6, 2));
  EXPECT_NE(other.transmittance.mean, r[0].transmittance.mean);
}

TEST(MC_SUITE(McEnergy), LaunchedWeightIsAccountedFor) {
  // Three layers (ballistic air-like, scattering tissue, ballistic glass), mismatched
  // indices everywhere, disk source: every weight path of the kernel is used.
  tocd::sim::mesh::SlabSpec spec;
  spec.width_mm = spec.depth_mm = 6.0;
  spec.cells_x = spec.cells_y = 6;
  spec.layers = {{0.5, 3, 2}, {1.0, 1, 4}, {0.5, 2, 2}};
  const mc::PreparedMesh mesh = mc::prepare(tocd::sim::mesh::make_slab(spec));
  mc::Optics optics;
  optics.regions[1] = props(0.5, 10.0, 0.8, 1.4);
  optics.regions[2] = props(0.01, 0.0, 0.0, 1.5);
  optics.regions[3] = props(0.001, 0.001, 1.0, 1.003);
  mc::Source disk;
  disk.kind = mc::Source::Kind::disk;
  disk.origin = {0.3, 0.0, 5.0};
  disk.radius_mm = 4.0;  // partly beyond the 6 mm slab: some photons miss it
  const mc::Result r = mc::run(mesh, optics, disk, settings(20000, 3));
  EXPECT_GT(r.missed.mean, 0.0);
  EXPECT_GT(r.side_loss.mean, 0.0);
  EXPECT_NE(r.roulette_balance.mean, 0.0);
  EXPECT_EQ(r.lost.mean, 0.0);
  EXPECT_LT(std::abs(r.energy_balance_error), 1e-9);
  double by_region = 0.0, by_tet = 0.0, by_marker = 0.0;
  for (const auto& [id, e] : r.absorbed_by_region) by_region += e.mean;
  for (double a : r.absorbed_per_tet) by_tet += a;
  for (const auto& [m, e] : r.exit_by_marker) by_marker += e.mean;
  EXPECT_NEAR(by_region, r.absorbed.mean, 1e-12);
  EXPECT_NEAR(by_tet, r.absorbed.mean, 1e-12);
  EXPECT_NEAR(by_marker, r.transmittance.mean + r.reflectance.mean + r.side_loss.mean, 1e-12);
}

TEST(MC_SUITE(McEnergy), BatchesOfOnePhotonAreTransportedWhole) {
  // One photon per batch: a thread keeps eight packets in flight (one per vector lane), so the
  // other lanes find the batch used up while the first packet still has to run. Every launched
  // photon must still be transported to the end; a skipped one would leave its weight
  // unaccounted for.
  const mc::PreparedMesh mesh = slab(10.0, 1.0);
  auto s = settings(20, 5);
  s.batches = 20;
  const mc::Result r =
      mc::run(mesh, one_region(props(0.1, 10.0, 0.9, 1.4)), pencil(0.0, 0.0123, -0.0217, 1.0), s);
  EXPECT_EQ(r.photons, 20u);
  EXPECT_GT(r.events, 20u);
  EXPECT_LT(std::abs(r.energy_balance_error), 1e-9);
}

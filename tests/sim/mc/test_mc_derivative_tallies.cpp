// The transmittance derivatives' tallies (RunSettings::transmittance_derivatives) go through
// the exact sums like every tally, and the switch changes nothing else. Light enough for the
// sanitizer stage; the physics of the derivatives is in test_mc_derivatives.cpp.
#include <gtest/gtest.h>

#include "slab_fixture.hpp"
#include "tocd/sim/mc/output.hpp"

namespace mc = tocd::sim::mc;
namespace msh = tocd::sim::mesh;
using namespace tocd::sim::mc::testing;

namespace {

mc::RunSettings with_derivatives(std::uint64_t photons, std::uint64_t seed, int threads) {
  mc::RunSettings s = settings(photons, seed, threads);
  s.transmittance_derivatives = true;
  s.tally_per_tet = false;
  return s;
}

// Two stacked scattering layers: region 1 on top, region 2 below.
mc::PreparedMesh two_layers() {
  msh::SlabSpec spec;
  spec.width_mm = spec.depth_mm = 20.0;
  spec.cells_x = spec.cells_y = 4;
  spec.layers = {{0.5, 1, 2}, {0.5, 2, 2}};
  return mc::prepare(msh::make_slab(spec));
}

}  // namespace

// The derivative tallies go through the exact sums: bitwise the same for 1 and 2 threads,
// and for the run split into two blocks of batches (as MPI ranks share it) and summed.
TEST(McDerivativeTallies, ReproducibleForAnyThreadsAndBlocks) {
  const mc::PreparedMesh mesh = two_layers();
  mc::Optics optics;
  optics.regions[1] = props(0.1, 10.0, 0.9, 1.4);
  optics.regions[2] = props(0.5, 4.0, 0.8, 1.4);
  const mc::Source beam = pencil(0.0, 0.0123, -0.0217, 1.0);
  const mc::Result one = mc::run(mesh, optics, beam, with_derivatives(10000, 41, 1));
  const mc::Result two = mc::run(mesh, optics, beam, with_derivatives(10000, 41, 2));
  const mc::RunSettings s = with_derivatives(10000, 41, 2);
  mc::Tallies blocks = mc::run_batches(mesh, optics, beam, s, 0, 7);
  const mc::Tallies rest = mc::run_batches(mesh, optics, beam, s, 7, s.batches);
  for (std::size_t i = 0; i < blocks.words.size(); ++i) blocks.words[i] += rest.words[i];
  const mc::Result split = mc::finish(mesh, optics, s, blocks);
  ASSERT_EQ(one.transmittance_derivatives.size(), 2u);
  for (const auto& [id, d] : one.transmittance_derivatives) {
    for (const mc::Result* other : {&two, &split}) {
      const auto& e = other->transmittance_derivatives.at(id);
      EXPECT_EQ(e.dT_dmu_a.mean, d.dT_dmu_a.mean) << id;
      EXPECT_EQ(e.dT_dmu_a.se, d.dT_dmu_a.se) << id;
      EXPECT_EQ(e.dT_dmu_s.mean, d.dT_dmu_s.mean) << id;
      EXPECT_EQ(e.dT_dmu_s.se, d.dT_dmu_s.se) << id;
    }
  }
}

// Off, the result has no derivatives (nor their JSON key); on or off, the photon histories
// and so every other tally are bitwise the same.
TEST(McDerivativeTallies, SwitchChangesNothingElse) {
  const mc::PreparedMesh mesh = slab(20.0, 1.0, 4, 2);
  const mc::Optics tissue = one_region(props(0.1, 10.0, 0.9, 1.4));
  const mc::Source beam = pencil(0.0, 0.0123, -0.0217, 1.0);
  mc::RunSettings s = settings(10000, 43, 2);
  const mc::Result off = mc::run(mesh, tissue, beam, s);
  s.transmittance_derivatives = true;
  const mc::Result on = mc::run(mesh, tissue, beam, s);
  EXPECT_TRUE(off.transmittance_derivatives.empty());
  EXPECT_EQ(on.transmittance_derivatives.size(), 1u);
  EXPECT_EQ(on.transmittance.mean, off.transmittance.mean);
  EXPECT_EQ(on.transmittance.se, off.transmittance.se);
  EXPECT_EQ(on.reflectance.mean, off.reflectance.mean);
  EXPECT_EQ(on.absorbed.mean, off.absorbed.mean);
  EXPECT_EQ(on.roulette_balance.mean, off.roulette_balance.mean);
  EXPECT_EQ(on.events, off.events);
  EXPECT_EQ(on.face_hits, off.face_hits);
  EXPECT_EQ(on.absorbed_per_tet, off.absorbed_per_tet);
  EXPECT_FALSE(mc::to_json(off).contains("transmittance_derivatives"));
  const auto j = mc::to_json(on);
  ASSERT_TRUE(j.contains("transmittance_derivatives"));
  EXPECT_EQ(j["transmittance_derivatives"]["1"]["dT_dmu_a_mm"]["mean"].get<double>(),
            on.transmittance_derivatives.at(1).dT_dmu_a.mean);
}

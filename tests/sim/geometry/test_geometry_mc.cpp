// The Monte Carlo runs on the composite mesh: regions and markers are what it consumes.
#include <gtest/gtest.h>

#include "mesh_cache.hpp"
#include "tocd/sim/mc/run.hpp"

namespace geo = tocd::sim::geometry;
namespace mc = tocd::sim::mc;
using geo::testing::Case;

namespace {

mc::Optics published_optics() {
  mc::Optics o;
  const mc::RegionOptics glass{0.001, 0.001, 1.0, 1.458, "glass"};
  o.regions[geo::pin] = glass;
  o.regions[geo::slide] = glass;
  o.regions[geo::air] = {0.001, 0.001, 1.0, 1.003, "air"};
  o.regions[geo::skin] = {0.089, 28.9, 0.926, 1.38, "skin"};
  o.regions[geo::compressed] = {0.089, 28.9, 0.926, 1.38, "compressed"};
  return o;
}

mc::Result run(Case c, std::uint64_t photons) {
  const mc::PreparedMesh mesh = mc::prepare(geo::testing::mesh_of(c).mesh);
  mc::Source source;
  source.kind = mc::Source::Kind::marker;
  source.marker = geo::pin_top;
  mc::RunSettings s;
  s.photons = photons;
  s.seed = 7;
  s.batches = 10;
  return mc::run(mesh, published_optics(), source, s);
}

}  // namespace

TEST(GeometryMc, CompositeIsTransportable) {
  const mc::Result r = run(Case::indent_10, 4000);
  EXPECT_LT(std::abs(r.energy_balance_error), 1e-12);
  EXPECT_EQ(r.lost.mean, 0.0);
  EXPECT_EQ(r.missed.mean, 0.0);
  EXPECT_GT(r.transmittance.mean, 0.0);
  // Light leaves through the slide bottom (marker 1) and is absorbed in skin and compressed.
  EXPECT_GT(r.exit_by_marker.at(geo::slide_bottom).mean, 0.0);
  EXPECT_NEAR(r.exit_by_marker.at(geo::slide_bottom).mean, r.transmittance.mean, 1e-12);
  EXPECT_GT(r.absorbed_by_region.at(geo::skin).mean, 0.0);
  EXPECT_GT(r.absorbed_by_region.at(geo::compressed).mean, 0.0);
}

TEST(GeometryMc, BaselineTransmitsTheLightInsideTheCriticalAngle) {
  // Glass only: collimated light going down the pin meets the hemispherical tip at
  // asin(r / R); inside the glass-air critical angle (r < R / 1.458, 47 % of the top face)
  // it leaves the tip and crosses the thin air gap into the slide, the rest is totally
  // reflected first. Fresnel losses at the three faces take < 15 % of the direct part.
  const mc::Result r = run(Case::baseline, 4000);
  EXPECT_LT(std::abs(r.energy_balance_error), 1e-12);
  const double direct = 1.0 / (1.458 * 1.458);
  EXPECT_GT(r.transmittance.mean, 0.85 * direct - 3 * r.transmittance.se);
  EXPECT_LT(r.transmittance.mean, 0.75);
  EXPECT_GT(r.transmittance.mean, run(Case::indent_10, 4000).transmittance.mean);
}

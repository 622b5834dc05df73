// Slabs against the adding-doubling reference values (docs/model.md, "Monte Carlo reference values").
// Tolerance: 3 standard errors of this run + 3 of the reference + 0.2 % absolute, as the
// acceptance criterion states. The slabs are wide enough that side loss is below 1e-4
// (asserted), so a laterally finite mesh stands in for the infinite slab.
#include <cmath>

#include <gtest/gtest.h>

#include "slab_fixture.hpp"

namespace mc = tocd::sim::mc;
using namespace tocd::sim::mc::testing;

namespace {

struct Case {
  const char* name;
  double mu_a, mu_s, g, n, d, width;
  double rsp, rd, rd_se, tt, tt_se, a, a_se;
  std::uint64_t photons;
};

void check(const Case& c) {
  // Coarse tets: a homogeneous slab does not care, and the test stays fast.
  const mc::PreparedMesh mesh = slab(c.width, c.d, 6, 2);
  const mc::Result r = mc::run(mesh, one_region(props(c.mu_a, c.mu_s, c.g, c.n)),
                               pencil(0.0, 0.0123, -0.0217, c.d), settings(c.photons * kScale));
  auto within = [&](const char* what, const mc::Estimate& e, double ref, double ref_se) {
    const double tol = 3.0 * e.se + 3.0 * ref_se + 0.002;
    EXPECT_NEAR(e.mean, ref, tol) << c.name << ' ' << what << " = " << e.mean << " +- " << e.se;
  };
  within("Rd", r.reflectance, c.rd, c.rd_se);
  within("Tt", r.transmittance, c.tt, c.tt_se);
  within("A", r.absorbed, c.a, c.a_se);
  EXPECT_NEAR(r.specular.mean, c.rsp, 1e-12) << c.name;
  EXPECT_LT(r.side_loss.mean, 1e-4) << c.name << " side loss " << r.side_loss.mean;
  EXPECT_NEAR(r.energy_balance_error, 0.0, 1e-9);
  std::printf("%-22s Rd %.5f +- %.5f (ref %.5f)  Tt %.5f +- %.5f (ref %.5f)  A %.5f  side %.2e  %.0f ph/s\n",
              c.name, r.reflectance.mean, r.reflectance.se, c.rd, r.transmittance.mean, r.transmittance.se,
              c.tt, r.absorbed.mean, r.side_loss.mean, r.photons_per_second);
}

}  // namespace

TEST(MC_SUITE(McSlabReference), ClassicMatched) {
  check({"classic matched", 1.0, 9.0, 0.75, 1.0, 0.2, 20.0, 0.0, 0.09736, 4e-5, 0.66097, 6e-5, 0.24167, 4e-5,
         1000000});
}

TEST(MC_SUITE(McSlabReference), ClassicMismatched) {
  check({"classic n=1.5", 1.0, 9.0, 0.75, 1.5, 0.2, 20.0, 0.04, 0.08686, 4e-5, 0.49311, 9e-5, 0.38003, 7e-5,
         1000000});
}

TEST(MC_SUITE(McSlabReference), ThinLowAbsorption) {
  check({"thin low absorption", 0.01, 10.0, 0.9, 1.4, 1.0, 80.0, 1.0 / 36.0, 0.34146, 2e-4, 0.59358, 2e-4,
         0.03719, 1e-5, 500000});
}

TEST(MC_SUITE(McSlabReference), SkinMatched) {
  check({"skin 2.5 mm matched", 0.089, 28.9, 0.926, 1.0, 2.5, 50.0, 0.0, 0.54137, 2e-4, 0.11416, 1.3e-4,
         0.34447, 1.2e-4, 400000});
}

// Physics sanity of the composite FE + Monte Carlo pipeline (docs/model.md,
// "The published study"): orderings the published study shows, compared
// with tolerances from the Monte Carlo standard errors.
#include <cmath>

#include <gtest/gtest.h>

#include "tocd/sim/study/predictor.hpp"
#include "tocd/sim/study/study.hpp"
#include "tocd/test/mc_request.hpp"

namespace st = tocd::sim::study;

// The physics-long build runs the same cases with 10x the photons under its own suite name,
// so ctest names stay unique.
#ifdef TOCD_STUDY_LONG
#define STUDY_SUITE StudyPhysicsLong
#else
#define STUDY_SUITE StudyPhysics
#endif

namespace {

#ifdef TOCD_STUDY_LONG
constexpr std::uint64_t kPhotons = 400000;
#else
constexpr std::uint64_t kPhotons = 40000;
#endif

st::PredictionRequest request(double d_mm, const std::string& optics = "native") {
  st::PredictionRequest r = tocd::test::mc_request(d_mm, kPhotons, 11, 2);
  std::string label;
  st::apply_optics(optics, r, label);
  return r;
}

st::PredictionRequest baseline() {
  auto r = request(0.0);
  r.baseline = true;
  return r;
}

/// a - b in units of their combined standard error (independent runs).
double sigmas(const st::Prediction& a, const st::Prediction& b) {
  return (a.T - b.T) / std::hypot(a.T_stderr, b.T_stderr);
}

/// The published runs stayed below 3.5 % side loss. Light leaving the skin's and the air's
/// sides stays below 5 % always. With `raised_index` (a compressed region of raised index on
/// the slide) the total is not bounded: light the slide guides to its edges is physics, and
/// is checked against expect_guided_fraction instead (docs/study.md).
void expect_sane(const st::Prediction& p, const char* what, bool raised_index = false) {
  SCOPED_TRACE(what);
  EXPECT_GT(p.T, 0.0);
  EXPECT_GT(p.T_stderr, 0.0);
  EXPECT_LT(p.T_stderr, 0.05 * p.T);
  if (!raised_index) {
    EXPECT_LT(p.side_loss, 0.05);
  }
  EXPECT_GE(p.side_loss_slide, 0.0);
  EXPECT_LE(p.side_loss_slide, p.side_loss);
  EXPECT_LT(p.side_loss - p.side_loss_slide, 0.05);  // through the skin's and air's sides
  // Transmission is the weight leaving through the slide's bottom face (marker 1).
  EXPECT_NEAR(p.mc["exit_by_marker"]["1"]["mean"].get<double>(), p.T, 1e-12);
  EXPECT_LT(std::abs(p.mc["energy_balance_error"].get<double>()), 1e-9);
  EXPECT_EQ(p.mc["lost"]["mean"].get<double>(), 0.0);
}

/// Unpolarised Fresnel transmittance from index n1 into n2 at sin(theta_1) = u / n1.
double fresnel_T(double n1, double n2, double u) {
  const double s1 = u / n1, s2 = u / n2;
  if (s2 >= 1) return 0.0;
  const double c1 = std::sqrt(1 - s1 * s1), c2 = std::sqrt(1 - s2 * s2);
  const double rs = (n1 * c1 - n2 * c2) / (n1 * c1 + n2 * c2), rp = (n2 * c1 - n1 * c2) / (n2 * c1 + n1 * c2);
  return 1 - 0.5 * (rs * rs + rp * rp);
}

/// Independent estimate of the light the slide guides to its edges, per unit of transmitted
/// light, for diffuse (Lambertian) light in a zone of index n_zone resting on the glass: with
/// u = n sin(theta) conserved across the flat interfaces and u^2 uniform for a Lambertian
/// flux, light with n_skin < u < n_glass enters the glass and is trapped by total reflection
/// at its bottom (air) and top (native skin): weight int T_F d(u^2); light with u < 1 leaves
/// through the bottom: int T_F(zone->glass) T_F(glass->air) d(u^2). Their ratio assumes every
/// transmitted photon crossed the zone, so it bounds the simulated ratio from above; at 1.5 mm
/// the zone sits under the pin, where most transmitted light passes, so the simulation should
/// reach a good part of it (a quarter is asked).
double guided_per_transmitted(double n_zone) {
  const double n_glass = 1.458, n_skin = 1.38;
  double guided = 0, out = 0;
  const int steps = 20000;
  for (int k = 0; k < steps; ++k) {  // midpoint rule in u^2
    const double u = std::sqrt((k + 0.5) / steps) * n_zone;
    if (u > n_skin && u < n_glass) guided += fresnel_T(n_zone, n_glass, u);
    if (u < 1) out += fresnel_T(n_zone, n_glass, u) * fresnel_T(n_glass, 1.0, u);
  }
  return guided / out;
}

/// The light guided by the slide beyond what native skin sends there, as a fraction of T,
/// against the estimate above.
void expect_guided_fraction(const st::Prediction& raised, const st::Prediction& native, double n_zone) {
  const double ratio = (raised.side_loss_slide - native.side_loss_slide) / raised.T;
  const double estimate = guided_per_transmitted(n_zone);
  std::printf("slide-guided extra / T: simulated %.4f, Lambertian bound %.4f (n_zone %.3f)\n", ratio,
              estimate, n_zone);
  EXPECT_LT(ratio, estimate);
  EXPECT_GT(ratio, 0.25 * estimate);
}

}  // namespace

TEST(STUDY_SUITE, GlassOnlyIsHighestAndCompressionRaisesTransmission) {
  st::Predictor predictor;
  const auto p0 = predictor.predict(baseline());
  const auto p1 = predictor.predict(request(0.0));
  const auto p2 = predictor.predict(request(0.625));
  const auto p3 = predictor.predict(request(1.5));
  expect_sane(p0, "sim 0");
  expect_sane(p1, "sim 1");
  expect_sane(p2, "sim 2");
  expect_sane(p3, "sim 3");
  std::printf("T: sim0 %.5f+-%.5f sim1 %.5f+-%.5f sim2 %.5f+-%.5f sim3 %.5f+-%.5f\n", p0.T, p0.T_stderr, p1.T,
              p1.T_stderr, p2.T, p2.T_stderr, p3.T, p3.T_stderr);
  EXPECT_GT(sigmas(p0, p3), 3.0);
  EXPECT_GT(sigmas(p3, p2), 3.0);
  EXPECT_GT(sigmas(p2, p1), 3.0);
  // The FE found a compressed region at the deepest step, and the mesh carries it.
  EXPECT_GT(p3.fe_summary["compressed_volume_mm3"].get<double>(), 0.0);
  bool has_compressed = false;
  for (const auto& r : p3.mesh_stats["regions"])
    has_compressed |= r["region"] == 5 && r["tets"].get<int>() > 0;
  EXPECT_TRUE(has_compressed);
}

TEST(STUDY_SUITE, ClearingTheCompressedRegionRaisesTransmission) {
  st::Predictor predictor;
  const auto native = predictor.predict(request(1.5));
  const auto low_mua = predictor.predict(request(1.5, "a60"));
  const auto low_mus = predictor.predict(request(1.5, "s60"));
  const auto high_n = predictor.predict(request(1.5, "n110"));
  const auto all = predictor.predict(request(1.5, "a60s60n110"));
  std::printf("T at 1.5 mm: native %.5f+-%.5f a60 %.5f+-%.5f s60 %.5f+-%.5f n110 %.5f+-%.5f all %.5f+-%.5f\n",
              native.T, native.T_stderr, low_mua.T, low_mua.T_stderr, low_mus.T, low_mus.T_stderr, high_n.T,
              high_n.T_stderr, all.T, all.T_stderr);
  EXPECT_TRUE(low_mua.mesh_cached);  // optics change only: FE and mesh reused
  EXPECT_GT(sigmas(low_mua, native), 3.0);
  EXPECT_GT(sigmas(low_mus, native), 3.0);
  EXPECT_GT(sigmas(all, low_mua), 3.0);
  expect_sane(low_mua, "a60");
  expect_sane(low_mus, "s60");
  // Raising n alone raises T too (the compressed zone, in contact with the glass pin, takes
  // in more of the pin's light), less than the scattering change; part of the light it guides
  // through the zone leaves by the sides (its index step to the native skin around it).
  EXPECT_GT(sigmas(high_n, native), 3.0);
  EXPECT_LT(high_n.T - native.T, 0.5 * (low_mus.T - native.T));
  EXPECT_GT(high_n.side_loss, native.side_loss);
  // The extra side loss is light the slide guides: from n 1.518 it enters the glass (1.458)
  // at up to grazing angles, beyond the glass/skin critical angle (71 deg), and total
  // internal reflection at the slide's bottom and top keeps it in the glass to its edges.
  const double extra = high_n.side_loss - native.side_loss;
  const double extra_slide = high_n.side_loss_slide - native.side_loss_slide;
  std::printf("side loss (slide edges): native %.4f (%.4f) n110 %.4f (%.4f) all %.4f (%.4f)\n",
              native.side_loss, native.side_loss_slide, high_n.side_loss, high_n.side_loss_slide,
              all.side_loss, all.side_loss_slide);
  EXPECT_GT(extra_slide, 0.6 * extra);
  expect_sane(high_n, "n110", true);
  expect_sane(all, "a60s60n110", true);
  expect_guided_fraction(high_n, native, 1.1 * 1.38);
  expect_guided_fraction(all, native, 1.1 * 1.38);
}

TEST(STUDY_SUITE, ThinnerSkinAndGradedClearingTransmitMore) {
  st::Predictor predictor;
  auto thin = request(0.0);
  thin.thickness_mm = 1.5;
  const auto p_thin = predictor.predict(thin);
  const auto p_thick = predictor.predict(request(0.0));
  EXPECT_GT(sigmas(p_thin, p_thick), 3.0);
  // Graded optics are at least as clear as native skin everywhere: more light than the
  // geometry-only step; the quantised levels are all used somewhere under the pin.
  auto graded = request(1.5);
  graded.optics_model = "graded";
  const auto p_graded = predictor.predict(graded);
  const auto p_native = predictor.predict(request(1.5));
  expect_sane(p_graded, "graded", true);
  expect_guided_fraction(p_graded, p_native, 1.1 * 1.38);  // graded: up to the cleared 1.518
  EXPECT_GT(sigmas(p_graded, p_native), 3.0);
  const auto levels = p_graded.mesh_stats["graded_levels_tets"];
  ASSERT_EQ(levels.size(), 9u);
  EXPECT_GT(levels[8].get<int>(), 0);
  EXPECT_GT(levels[4].get<int>(), 0);
}

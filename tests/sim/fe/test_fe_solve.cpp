// Whole-model checks on the published case: outputs are consistent with each other, the
// compressed region is a closed CCW outline under the pin, and bad input is refused.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "tocd/sim/fe/solve.hpp"

namespace fe = tocd::sim::fe;

namespace {
const fe::FeResult& published() {
  static const fe::FeResult r = fe::solve(fe::FeModel::published_default(), {0.625, 1.25, 1.5});
  return r;
}
double signed_area(const std::vector<fe::Point2>& p) {
  double a = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const auto& u = p[k];
    const auto& v = p[(k + 1) % p.size()];
    a += 0.5 * (u.r_mm * v.z_mm - v.r_mm * u.z_mm);
  }
  return a;
}
/// The published case on a mesh half as fine, for the path's bookkeeping (cheap under the
/// sanitizers, where a solve of the default mesh to 1.5 mm takes minutes).
fe::FeModel coarse_model() {
  fe::FeModel m = fe::FeModel::published_default();
  m.mesh_refinement = 0.5;
  return m;
}
}  // namespace

TEST(FeSolve, PublishedCaseReachesOnePointFiveMillimetres) {
  const auto& r = published();
  ASSERT_TRUE(r.complete) << r.stop_reason;
  ASSERT_EQ(r.steps.size(), 3u);
  double prev = 0;
  for (const auto& s : r.steps) {
    EXPECT_GT(s.force_N, prev);  // monotone loading
    prev = s.force_N;
    // Penetration stays below the augmented-Lagrangian tolerance (0.1 % of d) or close to it.
    EXPECT_LT(s.max_penetration_mm, 2e-3 * s.displacement_mm);
    // The surface under the pin follows the pin tip.
    EXPECT_NEAR(s.top_surface.front().z_mm, 2.5 - s.displacement_mm, 2e-3 * s.displacement_mm);
    EXPECT_DOUBLE_EQ(s.top_surface.front().r_mm, 0.0);
    for (std::size_t k = 1; k < s.top_surface.size(); ++k)
      EXPECT_GT(s.top_surface[k].r_mm, s.top_surface[k - 1].r_mm);
    for (double J : s.element_J) EXPECT_GT(J, 0);
  }
}

TEST(FeSolve, CompressedRegionIsAClosedCcwOutlineUnderThePin) {
  const auto& s = published().steps.back();
  ASSERT_FALSE(s.compressed_outlines.empty());
  double area = 0, elements_area = 0;
  for (const auto& o : s.compressed_outlines) {
    EXPECT_GT(signed_area(o), 0);
    area += signed_area(o);
  }
  EXPECT_NEAR(area, s.compressed_area_mm2, 1e-12);
  // The outline encloses exactly the flagged elements: compare with the sum of their areas.
  for (std::size_t e = 0; e < s.mesh.quads.size(); ++e) {
    if (s.element_min_log_strain[e] > -0.5) continue;
    std::vector<fe::Point2> q;
    for (int n : s.mesh.quads[e]) q.push_back(s.mesh.nodes[n]);
    elements_area += signed_area(q);
  }
  EXPECT_NEAR(area, elements_area, 1e-9 * area);
  // Highest strain right under the tip: a point just below it is in the compressed region.
  EXPECT_LE(s.min_log_strain_at(0.01, s.top_surface.front().z_mm - 0.01), -0.5);
  EXPECT_TRUE(std::isnan(s.min_log_strain_at(1.0, 3.0)));
  EXPECT_TRUE(std::isnan(s.min_log_strain_at(-1.0, 1.0)));
  // Revolved volume lies between the area swept at the smallest and the largest radius.
  double rmax = 0;
  for (const auto& o : s.compressed_outlines)
    for (const auto& p : o) rmax = std::max(rmax, p.r_mm);
  EXPECT_GT(s.compressed_volume_mm3, 0);
  EXPECT_LT(s.compressed_volume_mm3, 2 * std::numbers::pi * rmax * area);
}

TEST(FeSolve, JsonSummaryCarriesTheSteps) {
  const nlohmann::json j = fe::to_json(published());
  EXPECT_EQ(j["steps"].size(), 3u);
  EXPECT_TRUE(j["complete"].get<bool>());
  EXPECT_NEAR(j["steps"][2]["nominal_strain"].get<double>(), 0.6, 1e-12);
  EXPECT_FALSE(j["steps"][2]["compressed_outlines"].empty());
}

TEST(FeSolve, BadInputIsRefused) {
  fe::FeModel m = fe::FeModel::published_default();
  m.thickness_mm = -1;
  EXPECT_THROW(fe::solve(m, {0.5}), fe::FeError);
  m = fe::FeModel::published_default();
  EXPECT_THROW(fe::solve(m, {2.5}), fe::FeError);  // displacement reaches the slide
  EXPECT_THROW(fe::solve(m, {3.0}), fe::FeError);  // beyond the slab
  EXPECT_THROW(fe::solve(m, {0.5, 0.2}), fe::FeError);
  EXPECT_THROW(fe::solve(m, {}), fe::FeError);
  EXPECT_THROW(fe::solve(m, {-0.1}), fe::FeError);
  m.material.D = {0.0, 0.0, 0.0};  // no bulk modulus
  EXPECT_THROW(fe::solve(m, {0.5}), fe::FeError);
  m = fe::FeModel::published_default();
  m.material = {{0.1, -0.08}, {2.0, 6.0}, {0.5}};  // unstable in compression
  try {
    fe::solve(m, {0.5});
    FAIL() << "unstable material accepted";
  } catch (const fe::FeError& e) {
    EXPECT_NE(std::string(e.what()).find("unstable"), std::string::npos) << e.what();
  }
  EXPECT_THROW(fe::parse_kinematics("3d"), fe::FeError);
  EXPECT_THROW(fe::parse_bottom("glued"), fe::FeError);
}

TEST(FeSolve, NonConvergenceGivesAPartialResultThatSaysWhere) {
  fe::FeModel m = fe::FeModel::published_default();
  m.solver.max_newton_iterations = 2;  // cannot converge from the first increment
  m.solver.min_step_mm = 0.01;
  const fe::FeResult r = fe::solve(m, {0.3, 0.6});
  EXPECT_FALSE(r.complete);
  EXPECT_NE(r.stop_reason.find("stopped at"), std::string::npos) << r.stop_reason;
  EXPECT_LT(r.steps.size(), 2u);
}

// A run's steps are one loading path: advancing a compression step by step must be the one
// solve over all of them, to the bit (same increments, step sizes and predictor), so that a
// prediction that continued from the previous step is reproduced from its stored path.
TEST(PinCompression, AdvancingStepByStepIsTheOneSolveOverThePathBitForBit) {
  const fe::FeResult whole = fe::solve(coarse_model(), {0.4, 0.8, 1.0});
  ASSERT_TRUE(whole.complete) << whole.stop_reason;
  fe::PinCompression c(coarse_model());
  const fe::FeResult first = c.advance({0.4});
  const fe::FeResult rest = c.advance({0.8, 1.0});
  ASSERT_TRUE(first.complete && rest.complete) << first.stop_reason << rest.stop_reason;
  std::vector<fe::FeStepResult> stepped = first.steps;
  stepped.insert(stepped.end(), rest.steps.begin(), rest.steps.end());
  ASSERT_EQ(stepped.size(), whole.steps.size());
  for (std::size_t k = 0; k < stepped.size(); ++k) {
    SCOPED_TRACE(k);
    EXPECT_EQ(stepped[k].force_N, whole.steps[k].force_N);
    EXPECT_EQ(stepped[k].newton_iterations, whole.steps[k].newton_iterations);
    EXPECT_EQ(stepped[k].load_increments, whole.steps[k].load_increments);
    ASSERT_EQ(stepped[k].displacement.size(), whole.steps[k].displacement.size());
    for (std::size_t n = 0; n < stepped[k].displacement.size(); ++n) {
      EXPECT_EQ(stepped[k].displacement[n].r_mm, whole.steps[k].displacement[n].r_mm);
      EXPECT_EQ(stepped[k].displacement[n].z_mm, whole.steps[k].displacement[n].z_mm);
    }
  }
  EXPECT_EQ(c.path_mm(), (std::vector<double>{0.4, 0.8, 1.0}));
  EXPECT_EQ(first.total_load_increments + rest.total_load_increments, whole.total_load_increments);
}

// The path's end state is the elastic solution at 1.5 mm whichever way it came: a hyperelastic
// pin compression has no history. What differs is the contact's enforcement: each path stops
// augmenting once the penetration is below the tolerance (1e-3 of the displacement,
// FeSolverSettings), so the two may end with penetrations up to 1.5e-3 mm apart, and the force
// by that times its slope, d ln F / d d, taken from the published steps at 1.25 and 1.5 mm.
TEST(PinCompression, TheSteppedPathEndsWhereASolveFromFirstTouchEnds) {
  const fe::FeResult direct = fe::solve(fe::FeModel::published_default(), {1.5});
  ASSERT_TRUE(direct.complete) << direct.stop_reason;
  const auto& steps = published().steps;
  const double log_slope = std::log(steps[2].force_N / steps[1].force_N) / (1.5 - 1.25);
  const double penetration_span = fe::FeSolverSettings{}.penetration_tolerance * 1.5;
  EXPECT_NEAR(steps.back().force_N / direct.steps.back().force_N, 1.0, log_slope * penetration_span);
  EXPECT_NEAR(steps.back().contact_radius_mm, direct.steps.back().contact_radius_mm, 0.05);
}

TEST(PinCompression, APathGoesForwardAndAStoppedOneNoFurther) {
  fe::PinCompression c(coarse_model());
  ASSERT_TRUE(c.advance({0.25}).complete);
  EXPECT_THROW(c.advance({0.25}), fe::FeError);  // not beyond where the path is
  EXPECT_THROW(c.advance({0.1}), fe::FeError);
  EXPECT_THROW(c.advance({2.6}), fe::FeError);  // beyond the slab
  EXPECT_TRUE(c.usable()) << "a refused advance leaves the path as it was";
  EXPECT_TRUE(c.advance({0.5}).complete);

  fe::FeModel no_bulk = coarse_model();
  no_bulk.material.D = {0.0, 0.0, 0.0};
  EXPECT_THROW(fe::PinCompression{no_bulk}, fe::FeError) << "the model's own error, as solve() gives";

  fe::FeModel m = coarse_model();
  m.solver.max_newton_iterations = 2;
  m.solver.min_step_mm = 0.01;
  fe::PinCompression stuck(m);
  EXPECT_FALSE(stuck.advance({0.3}).complete);
  EXPECT_FALSE(stuck.usable());
  EXPECT_THROW(stuck.advance({0.6}), fe::FeError);
}

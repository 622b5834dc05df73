// Mesh convergence of the published case at 1.5 mm: pin force within 1 % and the compressed
// region's outline within one element between the default mesh and a finer one (1.5x by
// default, 2x in the physics-long build). The plane-stress section's own mesh convergence runs in
// the physics-long build only; the default build checks that it reaches 1.5 mm.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "tocd/sim/fe/solve.hpp"

namespace fe = tocd::sim::fe;

namespace {
#ifdef TOCD_FE_LONG
constexpr double kFine = 2.0;
#define TOCD_FE_CONVERGENCE FeConvergenceLong
#else
constexpr double kFine = 1.5;
#define TOCD_FE_CONVERGENCE FeConvergence
#endif

double distance_to_set(const fe::Point2& p, const std::vector<std::vector<fe::Point2>>& set) {
  double best = 1e300;
  for (const auto& loop : set)
    for (std::size_t k = 0; k < loop.size(); ++k) {  // distance to each segment
      const auto& a = loop[k];
      const auto& b = loop[(k + 1) % loop.size()];
      const double dr = b.r_mm - a.r_mm, dz = b.z_mm - a.z_mm, L2 = dr * dr + dz * dz;
      const double t =
          L2 > 0 ? std::clamp(((p.r_mm - a.r_mm) * dr + (p.z_mm - a.z_mm) * dz) / L2, 0.0, 1.0) : 0.0;
      best = std::min(best, std::hypot(p.r_mm - a.r_mm - t * dr, p.z_mm - a.z_mm - t * dz));
    }
  return best;
}
}  // namespace

TEST(TOCD_FE_CONVERGENCE, ForceAndOutlineAtOnePointFiveMillimetres) {
  fe::FeModel coarse = fe::FeModel::published_default(), fine = coarse;
  fine.mesh_refinement = kFine;
  const fe::FeResult rc = fe::solve(coarse, {1.5}), rf = fe::solve(fine, {1.5});
  ASSERT_TRUE(rc.complete) << rc.stop_reason;
  ASSERT_TRUE(rf.complete) << rf.stop_reason;
  const auto &c = rc.steps.back(), &f = rf.steps.back();
  EXPECT_NEAR(c.force_N, f.force_N, 0.01 * f.force_N);
  // One element: the largest deformed edge among the coarse mesh's compressed elements.
  double h = 0;
  for (std::size_t e = 0; e < c.mesh.quads.size(); ++e) {
    if (c.element_min_log_strain[e] > -0.5) continue;
    const auto& q = c.mesh.quads[e];
    for (int k = 0; k < 4; ++k) {
      const auto& a = c.mesh.nodes[q[k]];
      const auto& b = c.mesh.nodes[q[(k + 1) % 4]];
      h = std::max(h, std::hypot(a.r_mm - b.r_mm, a.z_mm - b.z_mm));
    }
  }
  ASSERT_GT(h, 0);
  double moved = 0;
  for (const auto& loop : c.compressed_outlines)
    for (const auto& p : loop) moved = std::max(moved, distance_to_set(p, f.compressed_outlines));
  for (const auto& loop : f.compressed_outlines)
    for (const auto& p : loop) moved = std::max(moved, distance_to_set(p, c.compressed_outlines));
  EXPECT_LT(moved, h) << "outline moved " << moved << " mm, element size " << h << " mm";
}

// The published model's own kinematics. Past ~1.45 mm the plane-stress section's tangent turns
// indefinite (the Newton step climbs the energy); the solver then descends along the shifted
// tangent to the stable branch, and the loading stays monotone.
TEST(TOCD_FE_CONVERGENCE, PlaneStressReachesOnePointFiveMillimetres) {
  fe::FeModel coarse = fe::FeModel::published_default();
  coarse.kinematics = fe::Kinematics::plane_stress;
  const fe::FeResult rc = fe::solve(coarse, {1.25, 1.5});
  ASSERT_TRUE(rc.complete) << rc.stop_reason;
  EXPECT_GT(rc.steps[1].force_N, rc.steps[0].force_N) << "monotone loading";
}

#ifdef TOCD_FE_LONG
// That stable branch is the mesh's answer and not an artefact of the path only if a finer mesh
// finds the same force: within 1 %, the bound the axisymmetric case meets above (the difference
// is the coarse mesh's discretisation error). The finer plane-stress solve takes minutes, hence
// the physics-long build only.
TEST(TOCD_FE_CONVERGENCE, PlaneStressForceAtOnePointFiveMillimetresIsMeshConverged) {
  fe::FeModel coarse = fe::FeModel::published_default();
  coarse.kinematics = fe::Kinematics::plane_stress;
  fe::FeModel fine = coarse;
  fine.mesh_refinement = kFine;
  const fe::FeResult rc = fe::solve(coarse, {1.5}), rf = fe::solve(fine, {1.5});
  ASSERT_TRUE(rc.complete) << rc.stop_reason;
  ASSERT_TRUE(rf.complete) << rf.stop_reason;
  EXPECT_NEAR(rc.steps.back().force_N, rf.steps.back().force_N, 0.01 * rf.steps.back().force_N);
}
#endif

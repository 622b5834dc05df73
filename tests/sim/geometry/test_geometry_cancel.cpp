// TetGen meshes in a child process: a cancelled mesh ends without waiting for TetGen and
// leaves no process behind, and a mesh meshed that way is the one TetGen gives (the same
// nodes, tets and regions whether or not it could have been cancelled).
#include <atomic>
#include <cerrno>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>
#include <sys/wait.h>

#include "mesh_cache.hpp"
#include "tocd/core/error.hpp"

namespace geo = tocd::sim::geometry;
using geo::testing::Case;

namespace {

/// True when this process has no child left, exited or running.
bool no_child_left() {
  int status = 0;
  return waitpid(-1, &status, WNOHANG) < 0 && errno == ECHILD;
}

}  // namespace

TEST(CompositeCancel, ASetFlagEndsTheMeshAndItsProcess) {
  std::atomic<bool> cancel{true};
  EXPECT_THROW(geo::build_composite(geo::testing::spec_of(Case::indent_10), &cancel), tocd::Cancelled);
  EXPECT_TRUE(no_child_left());
}

TEST(CompositeCancel, AFlagSetWhileTetGenMeshesKillsIt) {
  // The paper preset takes TetGen seconds; the flag is set 50 ms in. How long the cancelled
  // call took is not asserted (a loaded machine may be slow to start the child); that it
  // threw and reaped its child is.
  auto spec = geo::testing::spec_of(Case::indent_15);
  spec.size = {"paper", 0, 0};
  std::atomic<bool> cancel{false};
  std::thread setter([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    cancel = true;
  });
  EXPECT_THROW(geo::build_composite(spec, &cancel), tocd::Cancelled);
  setter.join();
  EXPECT_TRUE(no_child_left());
}

TEST(CompositeCancel, AnUnsetFlagChangesNothing) {
  const auto spec = geo::testing::spec_of(Case::indent_10);
  const auto& plain = geo::testing::mesh_of(Case::indent_10);
  std::atomic<bool> cancel{false};
  const auto cancellable = geo::build_composite(spec, &cancel);
  ASSERT_EQ(cancellable.mesh.nodes.size(), plain.mesh.nodes.size());
  ASSERT_EQ(cancellable.mesh.tets.size(), plain.mesh.tets.size());
  EXPECT_EQ(cancellable.mesh.nodes, plain.mesh.nodes);
  EXPECT_EQ(cancellable.mesh.tets, plain.mesh.tets);
  EXPECT_EQ(cancellable.mesh.regions, plain.mesh.regions);
  EXPECT_EQ(cancellable.mesh.boundary_faces.size(), plain.mesh.boundary_faces.size());
  EXPECT_TRUE(no_child_left());
}

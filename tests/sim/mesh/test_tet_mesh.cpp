#include <gtest/gtest.h>

#include "tocd/sim/mesh/tet_mesh.hpp"

using tocd::sim::mesh::TetMesh;

namespace {
// The unit cube split into the 6 tets around its main diagonal: every tet positive.
TetMesh unit_cube() {
  TetMesh m;
  for (int i = 0; i < 8; ++i) m.nodes.push_back({double(i & 1), double((i >> 1) & 1), double(i >> 2)});
  m.tets = {{0, 1, 3, 7}, {0, 1, 7, 5}, {0, 5, 7, 4}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}};
  m.regions = {1, 1, 1, 2, 2, 2};
  return m;
}
}  // namespace

TEST(TetMesh, UnitTetHasVolumeOneSixth) {
  EXPECT_DOUBLE_EQ(tocd::sim::mesh::signed_volume({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), 1.0 / 6.0);
  // Swapping two nodes inverts the tet.
  EXPECT_DOUBLE_EQ(tocd::sim::mesh::signed_volume({0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}), -1.0 / 6.0);
}

TEST(TetMesh, CubeVolumesAddUpPerRegion) {
  const TetMesh cube = unit_cube();
  for (std::size_t t = 0; t < cube.tets.size(); ++t) EXPECT_GT(tocd::sim::mesh::tet_volume(cube, t), 0.0);
  EXPECT_NEAR(tocd::sim::mesh::region_volume(cube, -1), 1.0, 1e-15);
  EXPECT_NEAR(tocd::sim::mesh::region_volume(cube, 1), 0.5, 1e-15);
  EXPECT_NEAR(tocd::sim::mesh::region_volume(cube, 2), 0.5, 1e-15);
  EXPECT_EQ(tocd::sim::mesh::region_volume(cube, 3), 0.0);
}

// relabel(): a prepared mesh given other regions is the mesh prepare() lays out for the same
// tets with those regions, record for record, and transports photons the same.
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "slab_fixture.hpp"
#include "tocd/sim/mesh/mesh_error.hpp"

namespace mc = tocd::sim::mc;
namespace mesh = tocd::sim::mesh;
using namespace tocd::sim::mc::testing;

namespace {

// Two layers (regions 1 and 2), 1.5 mm thick, z from 0 up; tilted when asked.
mesh::TetMesh two_layer_slab(double rotation_deg = 0.0) {
  mesh::SlabSpec spec;
  spec.width_mm = spec.depth_mm = 4.0;
  spec.cells_x = spec.cells_y = 5;
  spec.layers = {{0.5, 1, 2}, {1.0, 2, 3}};
  spec.rotation_deg = rotation_deg;
  return mesh::make_slab(spec);
}

// Regions that cut across both layers and the kernel order: by the tet's first node's x and
// its index, with ids that are not those of the slab.
std::vector<std::int32_t> other_regions(const mesh::TetMesh& m) {
  std::vector<std::int32_t> regions(m.tets.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    regions[t] = m.nodes[static_cast<std::size_t>(m.tets[t][0])][0] > 0.3 ? 104 : (t % 3 == 0 ? 4 : 101);
  return regions;
}

template <class T, class A>
bool same_bytes(const std::vector<T, A>& a, const std::vector<T, A>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

}  // namespace

TEST(McRelabel, IsWhatPrepareLaysOutForTheSameTetsWithThoseRegions) {
  const mesh::TetMesh built = two_layer_slab(7.0);
  const mc::PreparedMesh base = mc::prepare(built);
  mesh::TetMesh expected_mesh = built;
  expected_mesh.regions = other_regions(built);
  const mc::PreparedMesh expected = mc::prepare(expected_mesh);

  const mc::PreparedMesh got = mc::relabel(base, other_regions(built));

  EXPECT_EQ(got.region_ids, (std::vector<std::int32_t>{4, 101, 104}));
  EXPECT_EQ(got.region_ids, expected.region_ids);
  EXPECT_EQ(got.mesh.regions, expected.mesh.regions);
  EXPECT_EQ(got.original_of, expected.original_of);
  EXPECT_TRUE(same_bytes(got.tets, expected.tets));
  EXPECT_TRUE(same_bytes(got.links, expected.links));
  ASSERT_EQ(got.groups.size(), expected.groups.size());
  for (std::size_t g = 0; g < got.groups.size(); ++g) {
    EXPECT_EQ(got.groups[g].marker, expected.groups[g].marker);
    EXPECT_EQ(got.groups[g].side, expected.groups[g].side);
  }
  // The base keeps its own regions: a relabelled copy, not an edit.
  EXPECT_EQ(base.region_ids, (std::vector<std::int32_t>{1, 2}));
  EXPECT_EQ(base.mesh.regions, built.regions);
}

TEST(McRelabel, TransportsPhotonsAsThePreparedMeshDoes) {
  const mesh::TetMesh built = two_layer_slab();
  mesh::TetMesh expected_mesh = built;
  expected_mesh.regions = other_regions(built);
  mc::Optics optics;
  optics.regions[4] = props(0.1, 10.0, 0.9, 1.4);
  optics.regions[101] = props(0.02, 2.0, 0.8, 1.33);
  optics.regions[104] = props(0.3, 20.0, 0.9, 1.5);
  const auto s = settings(4000, 5, 2);
  const mc::Result a = mc::run(mc::relabel(mc::prepare(built), other_regions(built)), optics,
                               pencil(0, 0.0123, -0.0217, 1.5), s);
  const mc::Result b = mc::run(mc::prepare(expected_mesh), optics, pencil(0, 0.0123, -0.0217, 1.5), s);
  // Bitwise: the same photons cross the same records.
  EXPECT_EQ(a.transmittance.mean, b.transmittance.mean);
  EXPECT_EQ(a.reflectance.mean, b.reflectance.mean);
  EXPECT_EQ(a.absorbed.mean, b.absorbed.mean);
  EXPECT_GT(a.transmittance.mean, 0.0);
}

TEST(McRelabel, AWrongCountIsAMeshErrorNamingBothCounts) {
  const mc::PreparedMesh base = mc::prepare(two_layer_slab());
  try {
    mc::relabel(base, std::vector<std::int32_t>(3, 1));
    FAIL() << "no error";
  } catch (const mesh::MeshError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("3 regions"), std::string::npos) << msg;
    EXPECT_NE(msg.find(std::to_string(base.mesh.tets.size()) + " tets"), std::string::npos) << msg;
  }
}

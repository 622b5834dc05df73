#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "tocd/sim/mesh/mesh_error.hpp"
#include "tocd/sim/mesh/slab_mesh.hpp"
#include "tocd/sim/mesh/tetgen_io.hpp"
#include "tocd/sim/mesh/topology.hpp"
#include "tocd/test/error_of.hpp"
#include "tocd/test/temp_dir.hpp"

namespace msh = tocd::sim::mesh;

namespace {

msh::TetMesh two_tets() {
  // Two tets sharing face (1, 2, 3).
  msh::TetMesh m;
  m.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  if (msh::tet_volume(m, 1) < 0) std::swap(m.tets[1][0], m.tets[1][1]);
  m.regions = {1, 2};
  return m;
}

template <class F>
std::string error_of(F&& f) {
  return tocd::test::error_of<msh::MeshError>(f);
}

}  // namespace

TEST(SlabMesh, VolumesMarkersAndAdjacency) {
  msh::SlabSpec spec;
  spec.width_mm = 4.0;
  spec.depth_mm = 3.0;
  spec.cells_x = 4;
  spec.cells_y = 3;
  spec.layers = {{0.5, 7, 2}, {1.5, 9, 3}};
  const msh::TetMesh m = msh::make_slab(spec);
  EXPECT_EQ(m.tets.size(), 4u * 3u * 5u * 6u);
  EXPECT_NEAR(msh::region_volume(m, 7), 4.0 * 3.0 * 0.5, 1e-12);
  EXPECT_NEAR(msh::region_volume(m, 9), 4.0 * 3.0 * 1.5, 1e-12);
  const auto adj = msh::validate(m);  // conforming, nothing inverted
  std::size_t boundary = 0;
  for (const auto& n : adj.neighbour)
    for (auto x : n) boundary += x < 0;
  EXPECT_EQ(boundary, m.boundary_faces.size());
  // Top and bottom: 2 triangles per cell face.
  std::size_t top = 0, bottom = 0;
  for (const auto& f : m.boundary_faces) {
    top += f.marker == msh::kSlabTopMarker;
    bottom += f.marker == msh::kSlabBottomMarker;
  }
  EXPECT_EQ(top, 24u);
  EXPECT_EQ(bottom, 24u);
  const auto box = msh::bounding_box(m);
  EXPECT_DOUBLE_EQ(box.max[2], 2.0);
  EXPECT_DOUBLE_EQ(box.min[0], -2.0);
}

TEST(SlabMesh, RotationKeepsVolumeAndOrientation) {
  msh::SlabSpec spec;
  spec.rotation_deg = 33.0;
  spec.rotation_axis = {0.3, 1.0, 0.2};
  const msh::TetMesh m = msh::make_slab(spec);
  EXPECT_NEAR(msh::region_volume(m, -1), 100.0, 1e-9);
  EXPECT_NO_THROW(msh::validate(m));
}

TEST(SlabMesh, BadSpecIsAConfigError) {
  msh::SlabSpec spec;
  spec.width_mm = -1.0;
  EXPECT_THROW(msh::make_slab(spec), tocd::ConfigError);
}

TEST(TetgenIo, RoundTripKeepsEverything) {
  msh::SlabSpec spec;
  spec.cells_x = spec.cells_y = 2;
  spec.layers = {{1.0, 3, 1}, {1.0, 4, 1}};
  const msh::TetMesh m = msh::make_slab(spec);
  const auto prefix = tocd::test::process_temp_path("slab");
  msh::write_tetgen(m, prefix);
  const msh::TetMesh back = msh::read_tetgen(prefix);
  EXPECT_EQ(back.nodes, m.nodes);
  EXPECT_EQ(back.tets, m.tets);
  EXPECT_EQ(back.regions, m.regions);
  ASSERT_EQ(back.boundary_faces.size(), m.boundary_faces.size());
  for (std::size_t i = 0; i < m.boundary_faces.size(); ++i) {
    EXPECT_EQ(back.boundary_faces[i].nodes, m.boundary_faces[i].nodes);
    EXPECT_EQ(back.boundary_faces[i].marker, m.boundary_faces[i].marker);
  }
}

TEST(TetgenIo, ReadsOneBasedFilesWithComments) {
  const auto prefix = tocd::test::process_temp_path("one_based");
  std::ofstream(prefix.string() + ".node")
      << "# tetgen output\n4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1 # apex\n";
  std::ofstream(prefix.string() + ".ele") << "1 4 1\n1 1 2 3 4 5\n";
  std::ofstream(prefix.string() + ".face") << "1 1\n1 1 2 3 -7\n";
  const msh::TetMesh m = msh::read_tetgen(prefix);
  ASSERT_EQ(m.tets.size(), 1u);
  EXPECT_EQ(m.tets[0], (std::array<std::int32_t, 4>{0, 1, 2, 3}));
  EXPECT_EQ(m.regions[0], 5);
  EXPECT_EQ(m.boundary_faces[0].marker, -7);
}

TEST(TetgenIo, BadFilesNameFileAndLine) {
  const auto prefix = tocd::test::process_temp_path("bad");
  std::ofstream(prefix.string() + ".node") << "2 3 0 0\n0 0 0 0\n1 1 x 0\n";
  const std::string msg = error_of([&] { msh::read_tetgen(prefix); });
  EXPECT_NE(msg.find("bad.node:3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'x'"), std::string::npos) << msg;

  std::ofstream(prefix.string() + ".node") << "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
  std::ofstream(prefix.string() + ".ele") << "1 4 0\n0 0 1 2 9\n";
  const std::string msg2 = error_of([&] { msh::read_tetgen(prefix); });
  EXPECT_NE(msg2.find("bad.ele:2"), std::string::npos) << msg2;
  EXPECT_NE(msg2.find("out of range"), std::string::npos) << msg2;

  EXPECT_NE(error_of([&] { msh::read_tetgen(tocd::test::process_temp_path("missing")); }).find("cannot open"),
            std::string::npos);
}

TEST(Validate, InvertedTetIsNamed) {
  msh::TetMesh m = two_tets();
  std::swap(m.tets[1][2], m.tets[1][3]);
  const std::string msg = error_of([&] { msh::validate(m); });
  EXPECT_NE(msg.find("tet 1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("inverted"), std::string::npos) << msg;
}

TEST(Validate, NonManifoldFaceIsNamed) {
  msh::TetMesh m = two_tets();
  m.nodes.push_back({-0.5, 0.5, 0.5});  // a third tet on face (1 2 3)... on the same side as tet 0
  m.tets.push_back({1, 2, 3, 5});
  if (msh::tet_volume(m, 2) < 0) std::swap(m.tets[2][0], m.tets[2][1]);
  m.regions.push_back(1);
  const std::string msg = error_of([&] { msh::build_face_adjacency(m); });
  EXPECT_NE(msg.find("non-manifold"), std::string::npos) << msg;
  EXPECT_NE(msg.find("shared by 3 tets"), std::string::npos) << msg;
}

TEST(Validate, HangingNodeIsNonConforming) {
  // Tet A has face (0 1 2) on z = 0; below it, three tets meet at a node in the middle of
  // that face instead of sharing it.
  msh::TetMesh m;
  m.nodes = {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}, {0, 0, 1}, {1, 1, 0}, {1, 1, -1}};
  m.tets = {{0, 1, 2, 3}, {0, 1, 4, 5}, {1, 2, 4, 5}, {2, 0, 4, 5}};
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    if (msh::tet_volume(m, t) < 0) std::swap(m.tets[t][0], m.tets[t][1]);
  m.regions = {1, 1, 1, 1};
  const std::string msg = error_of([&] { msh::validate(m); });
  EXPECT_NE(msg.find("non-conforming"), std::string::npos) << msg;
  EXPECT_NE(msg.find("tet "), std::string::npos) << msg;
}

TEST(Validate, UnknownBoundaryFaceAndBadNodeIndex) {
  msh::TetMesh m = two_tets();
  m.boundary_faces.push_back({{0, 1, 4}, 3});
  EXPECT_NE(error_of([&] { msh::validate(m); }).find("boundary face 0"), std::string::npos);
  m = two_tets();
  m.tets[0][3] = 17;
  EXPECT_NE(error_of([&] { msh::validate(m); }).find("tet 0 refers to node 17"), std::string::npos);
}

// The adjacency against an independent count: every sorted node triple of a tet face mapped
// to the tets that have it, on a slab whose nodes are renumbered at random (so the faces'
// smallest nodes, by which the adjacency groups them, fall in no regular pattern).
TEST(Validate, AdjacencyPairsExactlyTheTetsThatShareAFace) {
  msh::SlabSpec spec;
  spec.cells_x = 5;
  spec.cells_y = 4;
  spec.layers = {{0.5, 1, 3}, {1.0, 2, 4}};
  msh::TetMesh m = msh::make_slab(spec);
  std::vector<std::int32_t> renumber(m.nodes.size());
  std::iota(renumber.begin(), renumber.end(), 0);
  std::shuffle(renumber.begin(), renumber.end(), std::mt19937(7));
  std::vector<msh::Point3> nodes(m.nodes.size());
  for (std::size_t n = 0; n < nodes.size(); ++n) nodes[static_cast<std::size_t>(renumber[n])] = m.nodes[n];
  m.nodes = nodes;
  for (auto& tet : m.tets)
    for (auto& v : tet) v = renumber[static_cast<std::size_t>(v)];
  for (auto& f : m.boundary_faces)
    for (auto& v : f.nodes) v = renumber[static_cast<std::size_t>(v)];

  std::map<std::array<std::int32_t, 3>, std::vector<std::int32_t>> owners;
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (const auto& l : msh::kFaceLocalNodes) {
      std::array<std::int32_t, 3> key{m.tets[t][l[0]], m.tets[t][l[1]], m.tets[t][l[2]]};
      std::sort(key.begin(), key.end());
      owners[key].push_back(static_cast<std::int32_t>(t));
    }
  const msh::FaceAdjacency adj = msh::validate(m);
  std::size_t shared = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      const auto& l = msh::kFaceLocalNodes[static_cast<std::size_t>(f)];
      std::array<std::int32_t, 3> key{m.tets[t][l[0]], m.tets[t][l[1]], m.tets[t][l[2]]};
      std::sort(key.begin(), key.end());
      const auto& o = owners.at(key);
      ASSERT_LE(o.size(), 2u);
      const std::int32_t other = o.size() == 1 ? -1 : (o[0] == static_cast<std::int32_t>(t) ? o[1] : o[0]);
      EXPECT_EQ(adj.neighbour[t][static_cast<std::size_t>(f)], other) << "tet " << t << " face " << f;
      shared += other >= 0;
      if (other < 0) EXPECT_NE(adj.boundary_marker[t][static_cast<std::size_t>(f)], 0) << "tet " << t;
    }
  EXPECT_GT(shared, m.tets.size());  // most faces are inner ones
}

TEST(Validate, AdjacencyAloneNamesABadNodeIndex) {
  msh::TetMesh m = two_tets();
  m.tets[1][2] = -3;
  EXPECT_NE(error_of([&] { msh::build_face_adjacency(m); }).find("tet 1 refers to node -3"),
            std::string::npos);
}

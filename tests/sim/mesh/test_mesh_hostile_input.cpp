// Hostile mesh files and slab specs: every one is refused with an error naming the file, the
// line or the value and the accepted range, before anything large is allocated.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "tocd/core/error.hpp"
#include "tocd/sim/mesh/mesh_error.hpp"
#include "tocd/sim/mesh/slab_mesh.hpp"
#include "tocd/sim/mesh/tetgen_io.hpp"
#include "tocd/sim/mesh/topology.hpp"
#include "tocd/test/error_of.hpp"
#include "tocd/test/temp_dir.hpp"

namespace msh = tocd::sim::mesh;

namespace {

// Writes a valid one-tet mesh whose parts may be replaced, and returns the error of reading it.
std::string read_error(const std::string& name, const std::string& node, const std::string& ele,
                       const std::string& face = "") {
  const auto prefix = tocd::test::process_temp_path(name);
  std::ofstream(prefix.string() + ".node") << node;
  std::ofstream(prefix.string() + ".ele") << ele;
  if (!face.empty()) std::ofstream(prefix.string() + ".face") << face;
  return tocd::test::error_of<msh::MeshError>([&] { msh::read_tetgen(prefix); });
}

const std::string kNode = "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
const std::string kEle = "1 4 1\n0 0 1 2 3 5\n";

bool has(const std::string& msg, const std::string& part) {
  return msg.find(part) != std::string::npos;
}

}  // namespace

TEST(MeshHostile, ValidBaseMeshReads) {
  EXPECT_EQ(read_error("base", kNode, kEle, "1 1\n0 0 1 2 4\n"), "");
}

TEST(MeshHostile, AFirstNodeIndexBeyondEveryIntegerIsRefused) {
  const std::string big = read_error("big", "4 3 0 0\n1e37 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n", kEle);
  EXPECT_TRUE(has(big, "node indices must start at 0 or 1")) << big;
  EXPECT_TRUE(has(big, "big.node:2")) << big;
}

TEST(MeshHostile, NonFiniteCoordinatesAreRefusedWithFileAndLine) {
  const std::string nan = read_error("nan", "4 3 0 0\n0 0 0 0\n1 nan 0 0\n2 0 1 0\n3 0 0 1\n", kEle);
  EXPECT_TRUE(has(nan, "nan.node:3")) << nan;
  EXPECT_TRUE(has(nan, "coordinate x = nan")) << nan;
  EXPECT_TRUE(has(nan, "1e+06 mm")) << nan;
  const std::string inf = read_error("inf", "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 -inf 0\n3 0 0 1\n", kEle);
  EXPECT_TRUE(has(inf, "inf.node:4")) << inf;
  EXPECT_TRUE(has(inf, "coordinate y = -inf")) << inf;
  const std::string huge = read_error("huge", "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1e300\n", kEle);
  EXPECT_TRUE(has(huge, "coordinate z = 1e+300")) << huge;
}

TEST(MeshHostile, ValidateRefusesNonFiniteNodesBuiltInMemory) {
  msh::TetMesh m;
  m.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, std::numeric_limits<double>::quiet_NaN()}};
  m.tets = {{0, 1, 2, 3}};
  m.regions = {1};
  try {
    msh::validate(m);
    FAIL() << "a NaN node was accepted";
  } catch (const msh::MeshError& e) {
    EXPECT_TRUE(has(e.what(), "node 3 has coordinate z = nan")) << e.what();
  }
}

TEST(MeshHostile, HeaderCountsAreBoundedBeforeAllocating) {
  for (const std::string count : {"-1", "nan", "1e12", "2.5", "inf"}) {
    const std::string msg = read_error("count", count + " 3 0 0\n0 0 0 0\n", kEle);
    EXPECT_TRUE(has(msg, "count.node:1")) << count << ": " << msg;
    EXPECT_TRUE(has(msg, "node count")) << count << ": " << msg;
    EXPECT_TRUE(has(msg, "out of range: accepted 0 to")) << count << ": " << msg;
  }
  // A count the file could hold in principle but does not: the limit follows the file size.
  const std::string big = read_error("big", "1000 3 0 0\n0 0 0 0\n", kEle);
  EXPECT_TRUE(has(big, "accepted 0 to 2 ")) << big;
  const std::string tets = read_error("tets", kNode, "1e12 4 1\n0 0 1 2 3 5\n");
  EXPECT_TRUE(has(tets, "tets.ele:1: tet count 1000000000000 is out of range")) << tets;
  const std::string faces = read_error("faces", kNode, kEle, "-1 1\n0 0 1 2 4\n");
  EXPECT_TRUE(has(faces, "faces.face:1: face count -1 is out of range")) << faces;
}

TEST(MeshHostile, AttributeCountAndMarkerFlagAreChecked) {
  const std::string neg = read_error("attrs", kNode, "1 4 -1\n0 0 1 2 3\n");
  EXPECT_TRUE(has(neg, "attrs.ele:1: attribute count -1 is out of range: accepted 0 to 64")) << neg;
  const std::string many = read_error("attrs2", kNode, "1 4 1e9\n0 0 1 2 3\n");
  EXPECT_TRUE(has(many, "attribute count 1000000000")) << many;
  const std::string per = read_error("per", kNode, "1 nan 1\n0 0 1 2 3 5\n");
  EXPECT_TRUE(has(per, "nan nodes per tet; expected 4 or 10")) << per;
  const std::string flag = read_error("flag", kNode, kEle, "1 nan\n0 0 1 2 4\n");
  EXPECT_TRUE(has(flag, "boundary marker flag nan is out of range: accepted 0 to 1")) << flag;
}

TEST(MeshHostile, RegionAndMarkerOutsideInt32AreRefused) {
  const std::string region = read_error("region", kNode, "1 4 1\n0 0 1 2 3 1e30\n");
  EXPECT_TRUE(
      has(region, "region.ele:2: region attribute 1e+30 is not an integer in [-2147483648, 2147483647]"))
      << region;
  const std::string nan_region = read_error("nanregion", kNode, "1 4 1\n0 0 1 2 3 nan\n");
  EXPECT_TRUE(has(nan_region, "region attribute nan")) << nan_region;
  const std::string marker = read_error("marker", kNode, kEle, "1 1\n0 0 1 2 -1e30\n");
  EXPECT_TRUE(has(marker, "marker.face:2: boundary marker -1e+30 is not an integer")) << marker;
  // The int32 extremes themselves are fine.
  EXPECT_EQ(read_error("edge", kNode, "1 4 1\n0 0 1 2 3 2147483647\n", "1 1\n0 0 1 2 -2147483648\n"), "");
}

TEST(MeshHostile, DirectoryInsteadOfFileIsNamed) {
  const auto prefix = tocd::test::process_temp_path("dir");
  std::filesystem::create_directories(prefix.string() + ".node");
  try {
    msh::read_tetgen(prefix);
    FAIL() << "a directory was read as a mesh";
  } catch (const msh::MeshError& e) {
    EXPECT_TRUE(has(e.what(), "dir.node")) << e.what();
    EXPECT_TRUE(has(e.what(), "not a regular file")) << e.what();
  }
}

TEST(MeshHostile, SlabSizesAndCellCountsHaveStatedLimits) {
  auto error_of = [](const std::string& text, int cells) -> std::string {
    try {
      msh::make_slab(msh::parse_slab_spec(text, cells));
    } catch (const tocd::ConfigError& e) {
      return e.what();
    }
    return "";
  };
  const std::string deep = error_of("10x10x1e7", 20);
  EXPECT_TRUE(has(deep, "slab '10x10x1e7': 1e7 mm is out of range: accepted above 0 up to 1000 mm")) << deep;
  EXPECT_TRUE(has(error_of("inf x10x1", 20), "not a positive length")) << error_of("inf x10x1", 20);
  EXPECT_TRUE(has(error_of("infx10x1", 20), "out of range")) << error_of("infx10x1", 20);
  EXPECT_TRUE(has(error_of("10x10:1@99999999999", 20), "region '99999999999' is not an integer in"));
  EXPECT_TRUE(
      has(error_of("10x10x1", 100000), "slab cells across 100000 is out of range: accepted 1 to 1000"));
  // Within every size limit, but 1000 x 1000 cells across and ~1000 in z is 6e9 tets.
  const std::string tets = error_of("1000x1000x1000", 1000);
  EXPECT_TRUE(has(tets, "the limit is 10000000")) << tets;
  // Thin and wide: z cells clamp before the int cast and the tet limit refuses the slab.
  const std::string thin = error_of("1000x0.001x1000", 20);
  EXPECT_TRUE(has(thin, "the limit is 10000000")) << thin;
  EXPECT_EQ(error_of("10x10x2.5", 20), "");
}

// A repeated index leaves another item unset; it was reported as a "degenerate" tet (the unset
// one, all four nodes 0). The reader names the repeated index and its line instead.
TEST(MeshHostile, ARepeatedTetOrNodeIndexIsNamedAsSuch) {
  const std::string tet = read_error("tet_twice", "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 1 1 1\n",
                                     "2 4 1\n0 0 1 2 3 5\n0 1 2 3 4 5\n");
  EXPECT_TRUE(has(tet, "tet index 0 is given twice")) << tet;
  EXPECT_TRUE(has(tet, "tet_twice.ele:3")) << tet;
  EXPECT_FALSE(has(tet, "degenerate")) << tet;
  const std::string node = read_error("node_twice", "4 3 0 0\n0 0 0 0\n1 1 0 0\n1 0 1 0\n3 0 0 1\n", kEle);
  EXPECT_TRUE(has(node, "node index 1 is given twice")) << node;
  EXPECT_TRUE(has(node, "node_twice.node:4")) << node;
}

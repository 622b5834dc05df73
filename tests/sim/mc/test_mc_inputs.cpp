// Bad input gives a typed error that names what was wrong; good input round-trips.
#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "slab_fixture.hpp"
#include "tocd/sim/mc/output.hpp"
#include "tocd/sim/mesh/mesh_error.hpp"
#include "tocd/test/error_of.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/temp_dir.hpp"

namespace mc = tocd::sim::mc;
using namespace tocd::sim::mc::testing;

namespace {

using tocd::test::error_of;

const char* kGoodToml = R"(
ambient_n = 1.0
[region.1]
name = "skin"
mu_a = 0.089
mu_s = 28.9
g = 0.926
n = 1.38
[region.2]
mu_a = 0.001
mu_s = 0.001
g = 1.0
n = 1.458
)";

}  // namespace

TEST(McOptics, ParsesRegionsAndAmbient) {
  const mc::Optics o = mc::parse_optics_toml(kGoodToml);
  ASSERT_EQ(o.regions.size(), 2u);
  EXPECT_EQ(o.regions.at(1).name, "skin");
  EXPECT_DOUBLE_EQ(o.regions.at(1).mu_s_per_mm, 28.9);
  EXPECT_DOUBLE_EQ(o.regions.at(2).g, 1.0);
  EXPECT_DOUBLE_EQ(o.ambient_n, 1.0);
}

TEST(McOptics, BadValuesNameRegionAndKey) {
  auto err = [](const std::string& text) {
    return error_of<mc::OpticsError>([&] { mc::parse_optics_toml(text, "file.toml"); });
  };
  const std::string base = "[region.4]\nmu_a = 0.1\nmu_s = 1\n";
  EXPECT_NE(err(base + "g = 0.9\nn = 0\n").find("region 4: n = 0"), std::string::npos);
  EXPECT_NE(err(base + "g = 0.9\nn = -1.3\n").find("n = -1.3"), std::string::npos);
  EXPECT_NE(err(base + "g = 1.2\nn = 1.4\n").find("region 4: g = 1.2"), std::string::npos);
  EXPECT_NE(err(base + "g = -1\nn = 1.4\n").find("g = -1"), std::string::npos);
  EXPECT_NE(err(base + "n = 1.4\n").find("missing 'g'"), std::string::npos);
  EXPECT_NE(err(base + "g = 0.9\nn = 1.4\nmus = 3\n").find("unknown key 'mus'"), std::string::npos);
  EXPECT_NE(err("[region.x]\nmu_a=1\n").find("region id must be an integer"), std::string::npos);
  EXPECT_NE(err("[region.1\n").find("file.toml:1"), std::string::npos);
  EXPECT_NE(
      error_of<mc::OpticsError>([] { mc::load_optics_toml("/nonexistent/optics.toml"); }).find("cannot open"),
      std::string::npos);
}

TEST(McRunInput, MissingRegionIsNamed) {
  tocd::sim::mesh::SlabSpec spec;
  spec.layers = {{1.0, 1, 1}, {1.0, 5, 1}};
  const mc::PreparedMesh mesh = mc::prepare(tocd::sim::mesh::make_slab(spec));
  const std::string msg = error_of<mc::OpticsError>(
      [&] { mc::run(mesh, one_region(props(0.1, 1, 0.9, 1.4)), pencil(0, 0.01, 0.01, 2.0), settings(100)); });
  EXPECT_NE(msg.find("region 5"), std::string::npos) << msg;
}

TEST(McRunInput, BadOpticsInCodeAreRejectedByRun) {
  const mc::PreparedMesh mesh = slab(4.0, 1.0);
  for (const auto& bad : {props(0.1, 1, 0.9, 0.0), props(0.1, 1, 0.9, -1.0), props(0.1, 1, 1.5, 1.4),
                          props(-0.1, 1, 0.9, 1.4), props(0.1, 1, -1.0, 1.4)}) {
    EXPECT_THROW(mc::run(mesh, one_region(bad), pencil(0, 0.01, 0.01, 1.0), settings(100)), mc::OpticsError);
  }
}

TEST(McRunInput, SourceOutsideTheMesh) {
  const mc::PreparedMesh mesh = slab(4.0, 1.0);
  const mc::Optics optics = one_region(props(0.1, 1, 0.9, 1.4));
  const std::string msg =
      error_of<mc::SourceError>([&] { mc::run(mesh, optics, pencil(0, 10.0, 0.0, 1.0), settings(100)); });
  EXPECT_NE(msg.find("source outside the mesh"), std::string::npos) << msg;
  mc::Source up = pencil(0, 0.0, 0.0, -5.0);
  up.direction = {0, 0, 1};
  EXPECT_NO_THROW(mc::run(mesh, optics, up, settings(100)));  // from below, upwards: enters the bottom
  mc::Source marker;
  marker.kind = mc::Source::Kind::marker;
  marker.marker = 42;
  EXPECT_NE(
      error_of<mc::SourceError>([&] { mc::run(mesh, optics, marker, settings(100)); }).find("marker 42"),
      std::string::npos);
  mc::Source disk;
  disk.kind = mc::Source::Kind::disk;
  disk.origin = {20.0, 0.0, 3.0};
  disk.radius_mm = 1.0;
  EXPECT_THROW(mc::run(mesh, optics, disk, settings(100)), mc::SourceError);
}

TEST(McRunInput, InvertedTetIsAMeshError) {
  tocd::sim::mesh::TetMesh m = tocd::sim::mesh::make_slab({});
  std::swap(m.tets[17][0], m.tets[17][1]);
  const std::string msg = error_of<tocd::sim::mesh::MeshError>([&] { mc::prepare(m); });
  EXPECT_NE(msg.find("tet 17"), std::string::npos) << msg;
  EXPECT_NE(msg.find("inverted"), std::string::npos) << msg;
}

TEST(McRunInput, BadSettings) {
  const mc::PreparedMesh mesh = slab(4.0, 1.0);
  const mc::Optics optics = one_region(props(0.1, 1, 0.9, 1.4));
  auto s = settings(100);
  s.batches = 1;
  EXPECT_THROW(mc::run(mesh, optics, pencil(0, 0.01, 0.01, 1.0), s), tocd::ConfigError);
  s = settings(100);
  s.ambient_n = 0.0;
  EXPECT_THROW(mc::run(mesh, optics, pencil(0, 0.01, 0.01, 1.0), s), tocd::ConfigError);
}

TEST(McSource, ParsesCommandLineForms) {
  const tocd::sim::mesh::BoundingBox box{{-5, -5, 0}, {5, 5, 2}};
  const mc::Source p = mc::parse_source("pencil", box);
  EXPECT_EQ(p.kind, mc::Source::Kind::pencil);
  EXPECT_DOUBLE_EQ(p.origin[0], 0.0);
  EXPECT_GT(p.origin[2], 2.0);
  const mc::Source d = mc::parse_source("disk:1,2,0.5,nospec", box);
  EXPECT_EQ(d.kind, mc::Source::Kind::disk);
  EXPECT_DOUBLE_EQ(d.radius_mm, 0.5);
  EXPECT_DOUBLE_EQ(d.origin[1], 2.0);
  EXPECT_FALSE(d.entry_specular);
  EXPECT_EQ(mc::parse_source("marker:3", box).marker, 3);
  const mc::Source q = mc::parse_source("pencil:0,0,1,0,1,-1", box);
  EXPECT_DOUBLE_EQ(q.direction[1], 1.0);
  EXPECT_THROW(mc::parse_source("laser", box), mc::SourceError);
  EXPECT_THROW(mc::parse_source("disk:1,2", box), mc::SourceError);
  EXPECT_THROW(mc::parse_source("marker:1.5", box), mc::SourceError);
  EXPECT_THROW(mc::parse_source("pencil:a,b", box), mc::SourceError);
}

TEST(McSource, MarkerSourceLightsThatFaceOnly) {
  // Marker 1 = slab top: collimated straight down over the whole top, weighted by area.
  const mc::PreparedMesh mesh = slab(4.0, 1.0, 4, 2);
  mc::Source top;
  top.kind = mc::Source::Kind::marker;
  top.marker = tocd::sim::mesh::kSlabTopMarker;
  const mc::Result r = mc::run(mesh, one_region(props(0.5, 0.0, 0.0, 1.0)), top, settings(2000));
  // Non-scattering, matched: every photon goes straight through, T = exp(-mu_a d) exactly.
  EXPECT_NEAR(r.transmittance.mean, std::exp(-0.5), 1e-12);
  EXPECT_EQ(r.side_loss.mean, 0.0);
}

TEST(McOutput, JsonAndVtu) {
  const mc::PreparedMesh mesh = slab(4.0, 1.0, 2, 1);
  const mc::Result r =
      mc::run(mesh, one_region(props(0.5, 5.0, 0.8, 1.4)), pencil(0, 0.01, 0.01, 1.0), settings(2000));
  const auto j = mc::to_json(r);
  EXPECT_EQ(j["photons"], 2000);
  EXPECT_DOUBLE_EQ(j["transmittance"]["mean"].get<double>(), r.transmittance.mean);
  EXPECT_TRUE(j["exit_by_marker"].contains("2"));
  const tocd::test::TempDir dir("mc");
  const auto path = dir / "fluence.vtu";
  mc::write_fluence_vtu(mesh, r, path);
  const std::string text = tocd::test::read_file(path);
  EXPECT_NE(text.find("NumberOfCells=\"" + std::to_string(mesh.tets.size()) + "\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"fluence\""), std::string::npos);
  EXPECT_NE(text.find("</VTKFile>"), std::string::npos);
  std::filesystem::remove(path);
  // Fluence is absorbed weight / (V mu_a).
  EXPECT_NEAR(r.fluence_per_tet[0], r.absorbed_per_tet[0] / (mesh.volume_mm3[0] * 0.5), 1e-15);
}

TEST(McRun, CancelStopsEarlyWithWholeBatches) {
  const mc::PreparedMesh mesh = slab(20.0, 1.0);
  std::atomic<bool> cancel{true};
  auto s = settings(200000);
  s.cancel = &cancel;
  std::uint64_t calls = 0;
  s.progress = [&](std::uint64_t, std::uint64_t) { ++calls; };
  const mc::Result r = mc::run(mesh, one_region(props(0.1, 10, 0.9, 1.4)), pencil(0, 0.01, 0.01, 1.0), s);
  EXPECT_TRUE(r.cancelled);
  EXPECT_LT(r.photons, 200000u);
}

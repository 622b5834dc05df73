// tocdlab's ParaView files as VTK itself reads them: a study's fluence .vtu files (binary and
// ASCII), their .pvd series and an FE step, loaded by check_vtu.py with Debian's python3-vtk9.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "tocd/sim/fe/solve.hpp"
#include "tocd/sim/study/study.hpp"
#include "tocd/test/temp_dir.hpp"

namespace st = tocd::sim::study;
namespace fe = tocd::sim::fe;
namespace vtk = tocd::sim::vtk;

namespace {

int check(const std::string& args) {
  const std::string cmd = fmt::format("{} {} {}", TOCD_SYSTEM_PYTHON, TOCD_CHECK_VTU, args);
  return std::system(cmd.c_str());
}

st::StudyTable study(const std::filesystem::path& dir, vtk::Format format, st::Predictor& predictor) {
  st::StudySettings s;
  s.photons = 20000;
  s.fluence_dir = dir.string();
  s.vtu_format = format;
  // Simulation 0: the glass-only baseline; 1: native skin with the pin 1.5 mm in.
  return st::run_study(predictor, st::sweep_cases(s, {1.5}, {2.5}, {"native"}), s, 0, 1);
}

}  // namespace

class ParaView : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(std::system(fmt::format("{} -c 'import vtkmodules.vtkIOXML'", TOCD_SYSTEM_PYTHON).c_str()), 0)
        << "VTK's Python modules are missing: apt-get install python3-vtk9 (scripts/bootstrap)";
  }
  tocd::test::TempDir dir_{"paraview"};
};

TEST_F(ParaView, StudyFluenceLoadsAsBinaryAndAsciiWithTheSameArraysAndASeries) {
  st::Predictor predictor;  // the second study reuses the first one's FE and meshes
  const st::StudyTable binary = study(dir_ / "binary", vtk::Format::binary, predictor);
  const st::StudyTable ascii = study(dir_ / "ascii", vtk::Format::ascii, predictor);
  ASSERT_EQ(binary.rows.size(), 2U);
  EXPECT_EQ(binary.rows[1].p.T, ascii.rows[1].p.T);  // the file format changes no result
  EXPECT_EQ(binary.fluence_series, (dir_ / "binary" / "fluence.pvd").string());
  for (const char* sim : {"sim00.vtu", "sim01.vtu"}) {
    // The target: binary under a quarter of ASCII, the same arrays and values (Float32 in both,
    // cells in the writer's order). Before: 0.42 and 0.45 with Float64 tallies in TetGen order.
    EXPECT_EQ(check(fmt::format("pair {} {} 0.25", (dir_ / "ascii" / sim).string(),
                                (dir_ / "binary" / sim).string())),
              0)
        << sim;
  }
  EXPECT_EQ(check(fmt::format("pvd {} 0,1", binary.fluence_series)), 0);
  EXPECT_EQ(check(fmt::format("pvd {} 0,1", ascii.fluence_series)), 0);
}

TEST_F(ParaView, FeStepHasReferencePointsAndADisplacementThatWarpsToThePinDepth) {
  const fe::FeModel model = fe::FeModel::published_default();
  const fe::FeResult r = fe::solve(model, {1.5});
  ASSERT_TRUE(r.complete) << r.stop_reason;
  fe::write_vtu(r.steps[0], dir_ / "fe_binary.vtu");
  fe::write_vtu(r.steps[0], dir_ / "fe_ascii.vtu", vtk::Format::ascii);
  EXPECT_EQ(check(fmt::format("pair {} {} 0.5", (dir_ / "fe_ascii.vtu").string(),
                              (dir_ / "fe_binary.vtu").string())),
            0);
  EXPECT_EQ(check(fmt::format("fe {} {} 1.5", (dir_ / "fe_binary.vtu").string(), model.thickness_mm)), 0);
}

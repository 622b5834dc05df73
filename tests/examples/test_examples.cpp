// The shipped examples parse with the project's own readers, and every example file is one
// this suite checks (a new file needs a test here).
#include <cmath>
#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "tocd/acquisition/protocol.hpp"
#include "tocd/devices/lab.hpp"
#include "tocd/sim/material/fit.hpp"
#include "tocd/sim/material/ogden.hpp"
#include "tocd/sim/mc/optics.hpp"
#include "tocd/sim/mesh/tet_mesh.hpp"
#include "tocd/sim/mesh/tetgen_io.hpp"
#if TOCD_WITH_PLOT_READERS
#include "tocd/plot/inputs.hpp"
#endif

namespace fs = std::filesystem;

namespace {

const fs::path kDir = TOCD_EXAMPLES_DIR;

}  // namespace

TEST(Examples, EveryFileIsCheckedHere) {
  const std::set<std::string> checked{"README.md",
                                      "lab/real-rig.toml",
                                      "protocols/pin-steps.toml",
                                      "protocols/vacuum-steps.toml",
                                      "optics/skin-on-glass-633nm.toml",
                                      "data/stress-strain.csv",
                                      "data/fluence_horizontal.csv",
                                      "data/fluence_vertical.csv",
                                      "mesh/skin-on-glass.node",
                                      "mesh/skin-on-glass.ele"};
  std::set<std::string> present;
  for (const auto& e : fs::recursive_directory_iterator(kDir))
    if (e.is_regular_file()) present.insert(fs::relative(e.path(), kDir).generic_string());
  EXPECT_EQ(present, checked);
}

TEST(Examples, RealRigLabConfigHasTheThreeInstrumentsOnTheirRealTransports) {
  const auto lab = tocd::devices::load_lab_config(kDir / "lab/real-rig.toml");
  ASSERT_TRUE(lab.tester && lab.power_meter && lab.vacuum);
  EXPECT_EQ(lab.tester->address.port, 502);
  EXPECT_EQ(lab.power_meter->transport, tocd::devices::PowerMeterConfig::Transport::usbtmc);
  EXPECT_EQ(lab.power_meter->vendor_id, 0x1313);
  EXPECT_EQ(lab.power_meter->wavelength_nm, 633.0);
  EXPECT_EQ(lab.vacuum->address.device, "/dev/ttyUSB0");
  EXPECT_EQ(lab.vacuum->address.parity, 'E');
}

TEST(Examples, PinProtocolStepsAreTheStrainsOnThe15mmSample) {
  const auto p = tocd::acquisition::load_protocol(kDir / "protocols/pin-steps.toml");
  EXPECT_EQ(p.kind, tocd::acquisition::StepKind::strain);
  ASSERT_EQ(p.steps.size(), 5u);
  // 50 % of 1.5 mm is 0.75 mm.
  EXPECT_NEAR(p.steps.back().displacement_mm, 0.75, 1e-12);
  EXPECT_NEAR(p.steps[2].nominal_strain, 0.25, 1e-12);
}

TEST(Examples, VacuumProtocolHasFourSetpoints) {
  const auto p = tocd::acquisition::load_protocol(kDir / "protocols/vacuum-steps.toml");
  EXPECT_EQ(p.kind, tocd::acquisition::StepKind::vacuum);
  ASSERT_EQ(p.steps.size(), 4u);
  EXPECT_DOUBLE_EQ(p.steps.front().pressure_kPa, 90.0);
  EXPECT_DOUBLE_EQ(p.steps.back().pressure_kPa, 30.0);
}

TEST(Examples, MeshIsTwoStacked2mmBlocksAndTheOpticsCoverItsRegions) {
  namespace msh = tocd::sim::mesh;
  const msh::TetMesh mesh = msh::read_tetgen(kDir / "mesh/skin-on-glass");
  ASSERT_EQ(mesh.tets.size(), 12u);
  // Each block is 2 x 2 x 1 mm = 4 mm^3, tets positively oriented.
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) EXPECT_GT(msh::tet_volume(mesh, t), 0.0) << "tet " << t;
  EXPECT_NEAR(msh::region_volume(mesh, 1), 4.0, 1e-12);
  EXPECT_NEAR(msh::region_volume(mesh, 2), 4.0, 1e-12);
  const auto optics = tocd::sim::mc::load_optics_toml(kDir / "optics/skin-on-glass-633nm.toml");
  for (auto r : mesh.regions) EXPECT_TRUE(optics.regions.count(r)) << "region " << r << " has no optics";
  EXPECT_DOUBLE_EQ(optics.regions.at(1).mu_s_per_mm, 28.9);
}

TEST(Examples, StressStrainIsThePublishedOgdenLaw) {
  namespace mat = tocd::sim::material;
  const auto d = mat::read_stress_strain_csv(kDir / "data/stress-strain.csv");
  ASSERT_EQ(d.strain.size(), 21u);
  // Independent of the file: the published law evaluated here; the file has 6 digits.
  const auto law = mat::OgdenParameters::published_skin();
  for (std::size_t k = 0; k < d.strain.size(); ++k) {
    const double expected = -mat::ogden_uniaxial_nominal_stress(law, 1.0 - d.strain[k]);
    EXPECT_NEAR(d.stress[k], expected, 1e-5 * std::abs(expected) + 1e-12) << "strain " << d.strain[k];
  }
}

#if TOCD_WITH_PLOT_READERS
TEST(Examples, FluenceSlicesAreHorizontalAndVerticalGrids) {
  const auto h = tocd::plot::read_slice_csv(kDir / "data/fluence_horizontal.csv");
  const auto v = tocd::plot::read_slice_csv(kDir / "data/fluence_vertical.csv");
  EXPECT_EQ(h.y_label, "y (mm)");
  EXPECT_EQ(v.y_label, "z (mm)");
  int positive = 0;
  for (double f : h.fluence) positive += f > 0 ? 1 : 0;
  EXPECT_GT(positive, h.nx * h.ny / 2);
}
#endif

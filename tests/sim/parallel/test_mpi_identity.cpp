// Results never depend on the number of MPI ranks or threads: each rank computes the same
// simulation alone (the reference) and shared with the other ranks, and the two must agree
// bit for bit: Monte Carlo tallies with per-tet fluence, a prediction, a study. Run under
// `mpirun -n 1|2|3` (see CMakeLists.txt). Collectives are entered by every rank whatever
// an earlier check found, so a failure is reported instead of hanging the job.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "run_facts.hpp"
#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/mesh/slab_mesh.hpp"
#include "tocd/sim/parallel/team.hpp"
#include "tocd/sim/study/study.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/mc_request.hpp"

namespace mc = tocd::sim::mc;
namespace st = tocd::sim::study;
namespace fs = std::filesystem;
using tocd::sim::parallel::Team;
using tocd::testing::drop_run_facts;

namespace {

Team& team() {
  return tocd::sim::parallel::world();
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

void expect_same(const mc::Estimate& a, const mc::Estimate& b, const std::string& what) {
  EXPECT_TRUE(same_bits(a.mean, b.mean)) << what << " mean " << a.mean << " vs " << b.mean;
  EXPECT_TRUE(same_bits(a.se, b.se)) << what << " se " << a.se << " vs " << b.se;
}

// Two layers (scattering skin under a clear top layer), so Fresnel, scattering, roulette and
// several regions and markers all take part.
mc::PreparedMesh two_layer_slab() {
  tocd::sim::mesh::SlabSpec spec;
  spec.width_mm = spec.depth_mm = 6.0;
  spec.cells_x = spec.cells_y = 4;
  spec.layers = {{0.3, 1, 2}, {1.0, 2, 3}};
  return mc::prepare(tocd::sim::mesh::make_slab(spec));
}

mc::Optics two_layer_optics() {
  mc::Optics o;
  o.regions[1] = {0.01, 0.0, 0.0, 1.5, "glass"};
  o.regions[2] = {0.2, 9.0, 0.85, 1.4, "skin"};
  return o;
}

}  // namespace

TEST(MpiIdentity, MonteCarloTalliesMatchOneProcessBitForBit) {
  const mc::PreparedMesh mesh = two_layer_slab();
  mc::Source beam;
  beam.origin = {0.0123, -0.0217, 1.3};
  beam.direction = {0.0, 0.0, -1.0};
  mc::RunSettings s;
  s.photons = 30000;
  s.seed = 17;
  s.batches = 20;
  s.tally_per_tet = true;
  s.threads = 1;
  const mc::Result alone = mc::run(mesh, two_layer_optics(), beam, s);  // this rank by itself
  for (int threads : {1, 2}) {
    s.threads = threads;
    s.team = &team();
    const mc::Result shared = mc::run(mesh, two_layer_optics(), beam, s);
    const std::string what =
        std::to_string(team().size()) + " ranks x " + std::to_string(threads) + " threads: ";
    EXPECT_EQ(shared.ranks, team().size());
    EXPECT_EQ(shared.photons, alone.photons);
    EXPECT_EQ(shared.batches, alone.batches);
    EXPECT_EQ(shared.events, alone.events);
    expect_same(shared.transmittance, alone.transmittance, what + "T");
    expect_same(shared.reflectance, alone.reflectance, what + "R");
    expect_same(shared.side_loss, alone.side_loss, what + "side");
    expect_same(shared.absorbed, alone.absorbed, what + "A");
    expect_same(shared.specular, alone.specular, what + "specular");
    for (const auto& [region, e] : alone.absorbed_by_region)
      expect_same(shared.absorbed_by_region.at(region), e, what + "region " + std::to_string(region));
    for (const auto& [marker, e] : alone.exit_by_marker)
      expect_same(shared.exit_by_marker.at(marker), e, what + "marker " + std::to_string(marker));
    ASSERT_EQ(shared.fluence_per_tet.size(), alone.fluence_per_tet.size());
    std::size_t differing = 0;
    for (std::size_t t = 0; t < alone.fluence_per_tet.size(); ++t)
      differing += !same_bits(shared.fluence_per_tet[t], alone.fluence_per_tet[t]) ||
                   !same_bits(shared.fluence_per_tet_se[t], alone.fluence_per_tet_se[t]) ||
                   !same_bits(shared.absorbed_per_tet[t], alone.absorbed_per_tet[t]);
    EXPECT_EQ(differing, 0u) << what << "per-tet tallies";
  }
}

TEST(MpiIdentity, PredictionMatchesOneProcessBitForBit) {
  st::PredictionRequest r = tocd::test::mc_request(0.6, 20000, 4, 2);
  r.thickness_mm = 1.5;
  r.max_edge_mm = 1.0;  // a coarse mesh: this checks identity, not accuracy
  r.tip_edge_mm = 0.2;
  // One folder for every rank (not a TempDir, whose name is the process's own): named by
  // mpirun's process id, which all ranks share.
  const fs::path dir = fs::temp_directory_path() / ("tocd_mpi_predict_" + std::to_string(::getppid()));
  r.fluence_dir = (dir / "shared").string();
  st::Predictor shared_predictor(1, &team());
  const st::Prediction shared = shared_predictor.predict(r);
  if (team().rank() != 0) return;  // every rank has the same result; rank 0 checks it
  r.fluence_dir = (dir / "alone").string();
  r.threads = 1;
  st::Predictor alone_predictor(1);
  const st::Prediction alone = alone_predictor.predict(r);
  EXPECT_TRUE(same_bits(shared.T, alone.T)) << shared.T << " vs " << alone.T;
  EXPECT_TRUE(same_bits(shared.T_stderr, alone.T_stderr));
  EXPECT_TRUE(same_bits(shared.side_loss, alone.side_loss));
  EXPECT_TRUE(same_bits(shared.side_loss_slide, alone.side_loss_slide));
  EXPECT_TRUE(same_bits(shared.reflectance, alone.reflectance));
  EXPECT_TRUE(same_bits(shared.absorbed, alone.absorbed));
  nlohmann::json a = alone.mc, b = shared.mc;
  drop_run_facts(a);
  drop_run_facts(b);
  EXPECT_EQ(a, b);
  for (const char* f : {"prediction.vtu", "prediction_horizontal.csv", "prediction_vertical.csv"}) {
    const std::string one = tocd::test::read_file(dir / "alone" / f),
                      many = tocd::test::read_file(dir / "shared" / f);  // rank 0 wrote both
    EXPECT_FALSE(one.empty()) << f;
    EXPECT_TRUE(one == many) << f << " differs";
  }
  fs::remove_all(dir);
}

namespace {

void expect_same_study(double split_photons) {
  st::StudySettings settings;
  settings.photons = 15000;
  settings.threads = 1;
  settings.seed = 8;
  settings.split_photons = static_cast<std::uint64_t>(split_photons);
  settings.max_edge_mm = 1.0;  // coarse meshes: this checks identity, not accuracy
  auto cases = st::sweep_cases(settings, {0.5}, {1.5}, {"native", "cleared"}, true);
  for (auto& c : cases) c.request.tip_edge_mm = 0.2;
  ASSERT_GE(cases.size(), 3u);
  st::Predictor shared_predictor(1, &team());
  const st::StudyTable shared = st::run_study(shared_predictor, cases, settings, 0, 1, {}, team());
  if (team().rank() != 0) {
    EXPECT_TRUE(shared.rows.empty());
    return;
  }
  st::Predictor alone_predictor(1);
  const st::StudyTable alone = st::run_study(alone_predictor, cases, settings, 0, 1);
  ASSERT_EQ(shared.rows.size(), alone.rows.size());
  for (std::size_t i = 0; i < alone.rows.size(); ++i) {
    EXPECT_TRUE(same_bits(shared.rows[i].p.T, alone.rows[i].p.T)) << "row " << i;
    EXPECT_TRUE(same_bits(shared.rows[i].rel_a, alone.rows[i].rel_a) ||
                (std::isnan(shared.rows[i].rel_a) && std::isnan(alone.rows[i].rel_a)))
        << "row " << i;
  }
  nlohmann::json a = st::to_json(alone), b = st::to_json(shared);
  drop_run_facts(a);
  drop_run_facts(b);
  EXPECT_EQ(a, b);
}

}  // namespace

TEST(MpiIdentity, StudyOfWholeSimulationsMatchesOneProcess) {
  expect_same_study(1e18);  // every simulation runs whole on one rank
}

TEST(MpiIdentity, StudyWithSharedBatchesMatchesOneProcess) {
  expect_same_study(1);  // every simulation's batches shared among the ranks
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  Team& t = team();
  if (t.rank() != 0) {  // one report for the job; a failing rank still fails the job
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int status = RUN_ALL_TESTS();
  // A rank that failed reports it through its exit status; mpirun then fails as a whole.
  tocd::sim::parallel::finish_world();
  return status;
}

// `tocdlab predict --db FILE --run ID --output-dir DIR`: a run's stored predictions re-run as
// one fluence .vtu per step plus run.pvd, which VTK's own reader (python3-vtk9) loads.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include "tocd/db/database.hpp"
#include "tocd/sim/study/predictor.hpp"
#include "tocd/test/cli.hpp"
#include "tocd/test/cli_test.hpp"
#include "tocd/test/temp_dir.hpp"

namespace fs = std::filesystem;
namespace st = tocd::sim::study;

namespace {

class RunSeries : public tocd::test::CliTest {
 protected:
  // A run with two steps whose stored configs are what the run engine stores: {"quantity",
  // "step", "baseline"}. Few photons: the series, not the physics, is under test.
  std::int64_t make_run(bool with_predictions) {
    tocd::db::Database db(db_);
    const auto run = db.create_run({}).id;
    for (int i = 0; i < 2; ++i) {
      tocd::db::StepRecord s;
      s.run_id = run;
      s.index = i;
      s.target_displacement_mm = 0.5 * (i + 1);
      db.add_step(s);
      if (!with_predictions) continue;
      st::PredictionRequest step, baseline;
      step.displacement_mm = s.target_displacement_mm;
      step.photons = baseline.photons = 2000;
      baseline.baseline = true;
      tocd::db::PredictionRecord p;
      p.run_id = run;
      p.step_index = i;
      p.config_json = nlohmann::json{{"quantity", "T(step) / T(baseline)"},
                                     {"step", st::to_config(step)},
                                     {"baseline", st::to_config(baseline)}}
                          .dump();
      p.T = 0.5;
      db.add_prediction(p);
    }
    db.set_run_status(run, tocd::db::RunStatus::completed);
    return run;
  }

  fs::path db_ = dir_ / "lab.sqlite";
};

}  // namespace

TEST_F(RunSeries, EachStepBecomesAVtuAndRunPvdLoadsWithItsSteps) {
  const auto run = make_run(true);
  const fs::path out = dir_ / "series";
  ASSERT_EQ(tocdlab(fmt::format("predict --db {} --run {} --output-dir {} --threads 2 --json", db_.string(),
                                run, out.string())),
            0)
      << err_;
  const auto j = nlohmann::json::parse(out_);
  ASSERT_EQ(j["steps"].size(), 2u);
  EXPECT_EQ(j["steps"][0]["step"], 1);
  EXPECT_EQ(j["steps"][1]["step"], 2);
  EXPECT_EQ(j["pvd"], (out / "run.pvd").string());
  for (const auto& s : j["steps"]) {
    EXPECT_TRUE(fs::exists(s["vtu"].get<std::string>()));
    const double T = s["T_step"].get<double>();
    EXPECT_GT(T, 0.0);  // some light crosses 2.5 mm of skin and the slide...
    EXPECT_LT(T, 1.0);  // ...never more than enters
  }
  const std::string check =
      fmt::format("{} {} pvd {} 1,2", TOCD_SYSTEM_PYTHON, TOCD_CHECK_VTU, (out / "run.pvd").string());
  EXPECT_EQ(std::system(check.c_str()), 0) << check;
}

TEST_F(RunSeries, RunWithoutPredictionsUnknownRunAndMissingDirAreClearErrors) {
  const auto run = make_run(false);
  EXPECT_EQ(tocdlab(fmt::format("predict --db {} --run {} --output-dir {}", db_.string(), run,
                                (dir_ / "x").string())),
            1);
  EXPECT_NE(err_.find("no stored predictions"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(dir_ / "x" / "run.pvd"));
  EXPECT_EQ(
      tocdlab(fmt::format("predict --db {} --run 99 --output-dir {}", db_.string(), (dir_ / "x").string())),
      1);
  EXPECT_NE(err_.find("99"), std::string::npos) << err_;
  // An option error: refused before anything runs, with the missing option named (exit code
  // as main.cpp gives every option error).
  EXPECT_NE(tocdlab(fmt::format("predict --db {} --run {}", db_.string(), run)), 0);
  EXPECT_NE(err_.find("--db requires --output-dir"), std::string::npos) << err_;
  EXPECT_TRUE(out_.empty());
}

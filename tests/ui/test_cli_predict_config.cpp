// The round trip docs/database.md promises: a prediction the run engine stores in
// predictions.config_json re-runs with `tocdlab predict --config` to the same T, bit for bit.
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

#include "tocd/db/reader.hpp"

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// One compression step, few photons: the run records it and predicts it (step / baseline).
constexpr const char* kProtocol = R"(name = "stored config round trip"
[sample]
tissue = "skin"
thickness_mm = 2.5
[baseline]
power_W = 1.0e-3
[motion]
contact_position_mm = 1.0
approach_speed_mm_per_s = 1.0
[steps]
displacements_mm = [0.5]
hold_s = 0.5
record_s = 1.0
[settle]
max_rate = 0.05
window_s = 0.5
max_wait_s = 5
[rates]
tester_Hz = 200
)";

class StoredConfig : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  int tocdlab(const std::string& args) {
    const std::string cmd =
        fmt::format("{} {} > {} 2> {}", TOCDLAB_EXE, args, (dir_ / "out").string(), (dir_ / "err").string());
    const int rc = std::system(cmd.c_str());
    out_ = slurp(dir_ / "out");
    err_ = slurp(dir_ / "err");
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  }

  fs::path dir_ = fs::temp_directory_path() / fmt::format("tocd_stored_config_{}", ::getpid());
  std::string out_, err_;
};

}  // namespace

TEST_F(StoredConfig, RunPredictionReRunsFromTheDatabaseToTheSameT) {
  std::ofstream(dir_ / "p.toml") << kProtocol;
  const fs::path db = dir_ / "lab.db";
  ASSERT_EQ(tocdlab(fmt::format("run {} --simulated --clock-factor 20 --photons 3000 --db {}",
                                (dir_ / "p.toml").string(), db.string())),
            0)
      << err_;

  tocd::db::PredictionRecord stored;
  {
    const tocd::db::Reader reader(db);
    const auto predictions = reader.predictions(1);
    ASSERT_EQ(predictions.size(), 1u);
    stored = predictions[0];
  }
  ASSERT_GT(stored.T, 0.0);
  // The stored document as the engine writes it: T(step) / T(baseline), both configs.
  const auto config = nlohmann::json::parse(stored.config_json);
  ASSERT_TRUE(config.contains("step"));
  ASSERT_TRUE(config["baseline"].is_object());
  std::ofstream(dir_ / "stored.json") << stored.config_json;

  ASSERT_EQ(tocdlab(fmt::format("predict --config {} --json", (dir_ / "stored.json").string())), 0) << err_;
  const auto again = nlohmann::json::parse(out_);
  EXPECT_EQ(again["T"].get<double>(), stored.T);  // bitwise: the same number, not a near one
  EXPECT_EQ(again["T_se"].get<double>(), stored.T_stderr);
  EXPECT_EQ(again["quantity"], config["quantity"]);
  EXPECT_EQ(again["config"]["step"], config["step"]);
  EXPECT_EQ(again["config"]["baseline"], config["baseline"]);

  // Its own --json output is a config too, with the same answer.
  std::ofstream(dir_ / "again.json") << out_;
  ASSERT_EQ(tocdlab(fmt::format("predict --config {} --json", (dir_ / "again.json").string())), 0) << err_;
  EXPECT_EQ(nlohmann::json::parse(out_)["T"].get<double>(), stored.T);

  // The text output states the quantity and the same T.
  ASSERT_EQ(tocdlab(fmt::format("predict --config {}", (dir_ / "stored.json").string())), 0) << err_;
  EXPECT_NE(out_.find(fmt::format("{:.6f}", stored.T)), std::string::npos) << out_;
  EXPECT_NE(out_.find("baseline"), std::string::npos) << out_;
}

TEST_F(StoredConfig, AStepThatIsNotAConfigIsRefusedByName) {
  std::ofstream(dir_ / "bad.json") << R"({"quantity": "x", "step": 3, "baseline": {}})";
  EXPECT_NE(tocdlab(fmt::format("predict --config {}", (dir_ / "bad.json").string())), 0);
  EXPECT_NE(err_.find("\"step\" must be a prediction config object"), std::string::npos) << err_;
}

// The round trip docs/database.md promises: a prediction the run engine stores in
// predictions.config_json re-runs with `tocdlab predict --config` to the same T, bit for bit.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include "tocd/db/reader.hpp"
#include "tocd/test/cli.hpp"
#include "tocd/test/cli_test.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/protocol_text.hpp"
#include "tocd/test/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

// One compression step, few photons: the run records it and predicts it (step / baseline).
std::string one_step_protocol() {
  tocd::test::PinProtocolText p;
  p.name = "stored config round trip";
  return tocd::test::protocol_toml(p);
}

using StoredConfig = tocd::test::CliTest;

}  // namespace

TEST_F(StoredConfig, RunPredictionReRunsFromTheDatabaseToTheSameT) {
  tocd::test::write_file(dir_ / "p.toml", one_step_protocol());
  const fs::path db = dir_ / "lab.db";
  ASSERT_EQ(
      tocdlab(fmt::format("run {} --simulated --sample analytic --clock-factor 20 --photons 3000 --db {}",
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

// What `predict --config` is given is read or refused, never replaced by the defaults: each
// of these gave exit 0 and the default prediction before.
TEST_F(StoredConfig, AConfigThatCannotBeReadAsWrittenIsRefusedNamingTheKey) {
  // A real config to edit: predict's own --json output (its "config").
  ASSERT_EQ(tocdlab("predict --displacement 0.5 --photons 2000 --json"), 0) << err_;
  const nlohmann::json good = nlohmann::json::parse(out_)["config"];
  ASSERT_EQ(good["kind"], "tocdlab.prediction");
  struct Case {
    std::string what;
    nlohmann::json config;
    std::string expect;
  };
  std::vector<Case> cases;
  auto edited = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json j = good;
    edit(j);
    return j;
  };
  cases.push_back({"misspelled key", edited([](auto& j) { j["displacment_mm"] = 1.0; }),
                   "unknown key \"displacment_mm\""});
  cases.push_back({"empty object", nlohmann::json::object(), "no \"kind\" key"});
  cases.push_back(
      {"wrong kind", edited([](auto& j) { j["kind"] = "tocdlab.study"; }), "\"kind\" is \"tocdlab.study\""});
  cases.push_back(
      {"unsupported version", edited([](auto& j) { j["version"] = 99; }), "\"version\" 99 is not supported"});
  cases.push_back({"negative mu_s", edited([](auto& j) { j["compressed_optics"]["mu_s"] = -28.9; }), "mu_s"});
  cases.push_back({"refractive index 0", edited([](auto& j) { j["compressed_optics"]["n"] = 0; }), "n"});
  cases.push_back({"edited region optics", edited([](auto& j) { j["optics"]["4"]["mu_s"] = -28.9; }),
                   "\"optics\" (region 4) differs"});
  cases.push_back({"unknown optics key", edited([](auto& j) { j["compressed_optics"]["mua"] = 0.1; }),
                   "unknown key \"mua\""});
  cases.push_back(
      {"unknown material key", edited([](auto& j) { j["material"]["Mu"] = {1.0}; }), "unknown key \"Mu\""});
  for (const auto& c : cases) {
    std::ofstream(dir_ / "edited.json") << c.config.dump();
    EXPECT_EQ(tocdlab(fmt::format("predict --config {}", (dir_ / "edited.json").string())), 1) << c.what;
    EXPECT_NE(err_.find(c.expect), std::string::npos) << c.what << ": " << err_;
    EXPECT_EQ(out_, "") << c.what;
  }
}

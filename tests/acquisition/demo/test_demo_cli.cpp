// `tocdlab demo` end to end (simulated lab, FE + Monte Carlo predictions) and `tocdlab fit --db`
// on the run it recorded, at low photon counts.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tocd/acquisition/compare_table.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::vector<std::string>> read_csv(const fs::path& p) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(slurp(p));
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    rows.push_back(cells);
  }
  return rows;
}

class Demo : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / fmt::format("tocd_demo_{}", ::getpid());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    rc_ = run(fmt::format("demo --db {} --photons 4000 --sample-photons 4000 --clock-factor 4",
                          (dir_ / "demo.db").string()));
    out_ = last_out_;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static int run(const std::string& args) {
    const std::string cmd =
        fmt::format("{} {} > {} 2> {}", TOCDLAB_EXE, args, (dir_ / "out").string(), (dir_ / "err").string());
    const int rc = std::system(cmd.c_str());
    last_out_ = slurp(dir_ / "out") + slurp(dir_ / "err");
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  }

  static inline fs::path dir_;
  static inline int rc_ = -1;
  static inline std::string out_, last_out_;
};

TEST_F(Demo, CompletesWithMeasuredAndPredictedTForEveryStep) {
  ASSERT_EQ(rc_, 0) << out_;
  EXPECT_NE(out_.find("predicted T"), std::string::npos) << out_;
  const auto rows = read_csv(dir_ / "demo.csv");
  ASSERT_EQ(rows.size(), 8u) << "header + 7 steps";
  std::vector<double> measured, predicted;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), 10u);
    ASSERT_FALSE(rows[i][5].empty()) << "measured T of step " << i;
    ASSERT_FALSE(rows[i][6].empty()) << "predicted T of step " << i;
    measured.push_back(std::stod(rows[i][5]));
    predicted.push_back(std::stod(rows[i][6]));
    EXPECT_GT(measured.back(), 0.0);
    EXPECT_LT(measured.back(), 1.0);
    EXPECT_GT(predicted.back(), 0.0);
    EXPECT_LT(predicted.back(), 1.0);
  }
  // Compression clears the tissue: deepest step transmits clearly more than contact, in the
  // simulated sample and in the model (differences far above the few-percent noise here).
  EXPECT_GT(measured.back(), 1.5 * measured.front());
  EXPECT_GT(predicted.back(), 1.5 * predicted.front());
}

TEST_F(Demo, CsvEqualsWhatTheDatabaseHolds) {
  ASSERT_EQ(rc_, 0) << out_;
  const tocd::db::Reader reader((dir_ / "demo.db").string());
  const auto runs = reader.runs();
  ASSERT_EQ(runs.size(), 1u);
  const auto table = tocd::acquisition::compare_table(reader, runs.front().run.id);
  EXPECT_EQ(tocd::acquisition::format_compare_csv(table), slurp(dir_ / "demo.csv"));
  EXPECT_EQ(table.status, "completed");
}

TEST_F(Demo, FitFromTheRecordedRun) {
  ASSERT_EQ(rc_, 0) << out_;
  const int rc = run(fmt::format("fit --db {} --run 1 --model ogden1", (dir_ / "demo.db").string()));
  EXPECT_EQ(rc, 0) << last_out_;
  EXPECT_NE(last_out_.find("ogden1 fit to"), std::string::npos) << last_out_;
  EXPECT_NE(last_out_.find("R^2"), std::string::npos) << last_out_;
  EXPECT_NE(run(fmt::format("fit --db {} --run 99", (dir_ / "demo.db").string())), 0);
  EXPECT_NE(last_out_.find("99"), std::string::npos) << last_out_;
}

}  // namespace

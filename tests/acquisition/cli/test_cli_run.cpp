// `tocdlab run / runs / compare / export` end to end on the simulated lab.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tocd/db/reader.hpp"

namespace fs = std::filesystem;
extern char** environ;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string protocol(double record_s) {
  return fmt::format(R"(name = "cli test"
[sample]
tissue = "skin"
thickness_mm = 2.5
[baseline]
power_W = 1.0e-3
[motion]
contact_position_mm = 1.0
approach_speed_mm_per_s = 1.0
[steps]
displacements_mm = [0.25, 0.5, 0.75]
hold_s = 0.5
record_s = {}
[settle]
max_rate = 0.05
window_s = 0.5
max_wait_s = 5
[rates]
tester_Hz = 200
)",
                     record_s);
}

class CliRun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           fmt::format("tocd_cli_{}_{}", ::getpid(),
                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Runs tocdlab with `args`; stdout and stderr go to out_ and err_. Returns the exit status.
  int tocdlab(const std::string& args) {
    const std::string cmd =
        fmt::format("{} {} > {} 2> {}", TOCDLAB_EXE, args, (dir_ / "out").string(), (dir_ / "err").string());
    const int rc = std::system(cmd.c_str());
    out_ = slurp(dir_ / "out");
    err_ = slurp(dir_ / "err");
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  }

  /// Like tocdlab(), with `prefix` run by the shell first (limits, traps) in the same process.
  int tocdlab_in_shell(const std::string& prefix, const std::string& args) {
    const std::string cmd = fmt::format("sh -c \"{}exec {} {}\" > {} 2> {}", prefix, TOCDLAB_EXE, args,
                                        (dir_ / "out").string(), (dir_ / "err").string());
    const int rc = std::system(cmd.c_str());
    out_ = slurp(dir_ / "out");
    err_ = slurp(dir_ / "err");
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  }

  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }

  fs::path dir_;
  std::string out_, err_;
};

}  // namespace

TEST_F(CliRun, RunsCompareExportOnTheSimulatedLab) {
  const auto p = write("p.toml", protocol(1.0));
  const auto db = dir_ / "lab.db";
  ASSERT_EQ(tocdlab(fmt::format("run {} --simulated --clock-factor 20 --photons 3000 --db {}", p.string(),
                                db.string())),
            0)
      << err_;
  // Progress and how the run ended on stderr; the table on stdout.
  EXPECT_NE(err_.find("step 3/3 recorded"), std::string::npos) << err_;
  EXPECT_NE(err_.find("run 1 completed"), std::string::npos) << err_;
  EXPECT_NE(out_.find("measured T"), std::string::npos) << out_;

  ASSERT_EQ(tocdlab(fmt::format("compare --db {} --run 1 --json", db.string())), 0) << err_;
  const auto j = nlohmann::json::parse(out_);
  ASSERT_EQ(j["steps"].size(), 3u);
  double previous_T = 0, previous_load = -1;
  for (const auto& s : j["steps"]) {
    // The simulated tissue clears and stiffens under compression: T and load rise step by step.
    EXPECT_GT(s["measured_T"].get<double>(), previous_T);
    EXPECT_GT(s["load_N"].get<double>(), previous_load);
    previous_T = s["measured_T"].get<double>();
    previous_load = s["load_N"].get<double>();
    // Every step predicted by the simulator (T relative to glass only, few photons here).
    ASSERT_FALSE(s["predicted_T"].is_null());
    EXPECT_GT(s["predicted_T"].get<double>(), 0.0);
    EXPECT_GT(s["predicted_T_se"].get<double>(), 0.0);
  }
  EXPECT_DOUBLE_EQ(j["steps"][1]["nominal_strain"].get<double>(), 0.2);

  ASSERT_EQ(tocdlab(fmt::format("runs --db {}", db.string())), 0) << err_;
  EXPECT_NE(out_.find("completed"), std::string::npos) << out_;
  ASSERT_EQ(tocdlab(fmt::format("export --db {} --run 1 --format csv", db.string())), 0) << err_;
  EXPECT_EQ(out_.rfind("step,", 0), 0u) << out_;
  EXPECT_EQ(std::count(out_.begin(), out_.end(), '\n'), 4);  // header + 3 steps
  ASSERT_EQ(tocdlab(fmt::format("export --db {} --run 1 --format json --max-points 10", db.string())), 0)
      << err_;
  EXPECT_TRUE(nlohmann::json::accept(out_));
}

TEST_F(CliRun, MalformedProtocolNamesLineAndKeyAndCreatesNothing) {
  auto text = protocol(1.0);
  text.replace(text.find("record_s = 1"), 12, "record_s = \"one\"");
  const auto p = write("bad.toml", text);
  const auto db = dir_ / "lab.db";
  EXPECT_EQ(tocdlab(fmt::format("run {} --simulated --no-predict --db {}", p.string(), db.string())), 1);
  EXPECT_NE(err_.find("bad.toml:13: [steps] record_s: must be a number"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(db));
}

TEST_F(CliRun, NotADatabaseIsRefusedAndLeftAlone) {
  const auto notdb = write("notes.db", "these are my notes, not a database\n");
  EXPECT_EQ(tocdlab(fmt::format("runs --db {}", notdb.string())), 1);
  EXPECT_NE(err_.find("error"), std::string::npos);
  EXPECT_EQ(slurp(notdb), "these are my notes, not a database\n");
  const auto p = write("p.toml", protocol(1.0));
  EXPECT_EQ(tocdlab(fmt::format("run {} --simulated --no-predict --db {}", p.string(), notdb.string())), 1);
  EXPECT_EQ(slurp(notdb), "these are my notes, not a database\n");
}

TEST_F(CliRun, SigintAbortsGracefullyAndTheRunResumes) {
  const auto p = write("p.toml", protocol(60.0));  // long recording windows
  const auto db = dir_ / "lab.db";
  const std::string out = (dir_ / "out").string();
  std::string exe = TOCDLAB_EXE, a1 = "run", a2 = p.string(), a3 = "--simulated", a4 = "--clock-factor",
              a5 = "5", a6 = "--db", a7 = db.string(), a8 = "--no-predict";
  char* args[] = {exe.data(), a1.data(), a2.data(), a3.data(), a4.data(),
                  a5.data(),  a6.data(), a7.data(), a8.data(), nullptr};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, exe.c_str(), &actions, nullptr, args, environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  // Wait for the first step to be recording (5 x faster: approach, settle, hold take ~0.5 s).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (slurp(out).find("recording into") == std::string::npos &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const std::string said = slurp(out);
  EXPECT_NE(said.find("run 1 aborted; all data kept"), std::string::npos) << said;
  {
    const tocd::db::Reader r(db);
    EXPECT_EQ(r.run(1).status, tocd::db::RunStatus::aborted);
    bool sigint = false;
    for (const auto& e : r.events(1)) sigint = sigint || e.message.find("abort: SIGINT") != std::string::npos;
    EXPECT_TRUE(sigint);
    EXPECT_GT(r.sample_count(r.channel(1, "load")->id), 100);
  }
  // --resume continues the same run; a shorter protocol is not needed: it redoes from step 1
  // at the clock of the other runs here (a faster one outruns a 200 Hz tester poller on a busy machine).
  ASSERT_EQ(
      tocdlab(fmt::format("run --resume 1 --simulated --no-predict --clock-factor 20 --db {}", db.string())),
      0)
      << err_;
  EXPECT_NE(err_.find("run 1 completed"), std::string::npos) << err_;
  const tocd::db::Reader r(db);
  EXPECT_EQ(r.runs().size(), 1u);
  EXPECT_EQ(r.steps(1).size(), 3u);
}

TEST_F(CliRun, AKilledRunIsShownInterruptedByEveryReaderWithoutWritingTheFile) {
  const auto p = write("p.toml", protocol(60.0));
  const auto db = dir_ / "lab.db";
  const std::string out = (dir_ / "out").string();
  std::string exe = TOCDLAB_EXE, a1 = "run", a2 = p.string(), a3 = "--simulated", a4 = "--clock-factor",
              a5 = "5", a6 = "--db", a7 = db.string(), a8 = "--no-predict";
  char* args[] = {exe.data(), a1.data(), a2.data(), a3.data(), a4.data(),
                  a5.data(),  a6.data(), a7.data(), a8.data(), nullptr};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, exe.c_str(), &actions, nullptr, args, environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (slurp(out).find("recording into") == std::string::npos &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));

  ASSERT_EQ(tocdlab(fmt::format("runs --db {}", db.string())), 0) << err_;
  EXPECT_NE(out_.find("interrupted"), std::string::npos) << out_;
  EXPECT_EQ(out_.find("running"), std::string::npos) << out_;
  ASSERT_EQ(tocdlab(fmt::format("compare --db {} --run 1", db.string())), 0) << err_;
  EXPECT_NE(out_.find("(interrupted)"), std::string::npos) << out_;
  ASSERT_EQ(tocdlab(fmt::format("compare --db {} --run 1 --json", db.string())), 0) << err_;
  EXPECT_EQ(nlohmann::json::parse(out_)["run"]["status"], "interrupted") << out_;
  // The readers presented it; the file still says what the dead process left (the next
  // writer marks it).
  const tocd::db::Reader r(db);
  EXPECT_EQ(r.run(1).status, tocd::db::RunStatus::running);
  EXPECT_EQ(r.shown_status(1), tocd::db::RunStatus::interrupted);
}

TEST_F(CliRun, ExitStatusIsNonZeroAndSaysHowManySamplesWereLostWhenTheFileCannotGrow) {
  const auto p = write("p.toml", protocol(60.0));
  const auto db = dir_ / "lab.db";
  // A 2 MiB file-size limit (SIGXFSZ ignored, so writes past it fail as on a full disk):
  // the database cannot hold the run's samples.
  const int rc = tocdlab_in_shell(
      "trap '' XFSZ; ulimit -f 4096; ",
      fmt::format("run {} --simulated --clock-factor 20 --no-predict --db {}", p.string(), db.string()));
  EXPECT_EQ(rc, 1) << out_ << err_;
  EXPECT_NE(err_.find("sample(s) were lost and are not in"), std::string::npos) << err_;
  EXPECT_NE(err_.find("lost to failed database commits"), std::string::npos) << err_;
  EXPECT_NE(err_.find("storage: a database commit failed"), std::string::npos) << err_;
}

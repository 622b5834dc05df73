// `tocdlab mc | study` under mpirun as a user runs them: the same JSON for 1, 2 and 3 ranks
// (timings aside), one JSON document on stdout however many ranks print, and a job that
// loses a rank fails as a whole and leaves no output file that looks complete.
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include "run_facts.hpp"
#include "tocd/test/cli.hpp"
#include "tocd/test/temp_dir.hpp"

namespace fs = std::filesystem;
using tocd::test::read_file;
using tocd::testing::drop_run_facts;

namespace {

class MpiCli : public ::testing::Test {
 protected:
  void SetUp() override {
    // Open MPI refuses to run as root without these (CI runs as root); no single-copy
    // mechanism (CMA needs ptrace rights that containers often withhold).
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    ::setenv("OMPI_MCA_btl_vader_single_copy_mechanism", "none", 1);
    std::ofstream(dir_ / "optics.toml") << "[region.1]\nmu_a = 0.2\nmu_s = 9.0\ng = 0.85\nn = 1.4\n";
  }

  std::string mpirun(int ranks) const {
    return fmt::format("{} -n {} --oversubscribe {}", MPIEXEC, ranks, TOCDLAB_EXE);
  }
  /// Runs a shell command; stdout and stderr go to out_ and err_. Returns the exit status.
  int shell(const std::string& cmd) {
    const tocd::test::CliResult r = tocd::test::run_shell(cmd, dir_);
    out_ = r.out;
    err_ = r.err;
    return r.status;
  }

  tocd::test::TempDir dir_{"mpi_cli"};
  std::string out_, err_;
};

}  // namespace

TEST_F(MpiCli, McJsonIsTheSameForOneTwoAndThreeRanks) {
  nlohmann::json reference;
  for (int ranks : {1, 2, 3}) {
    const auto vtu = dir_ / fmt::format("fluence{}.vtu", ranks);
    ASSERT_EQ(
        shell(fmt::format("{} mc --slab 6x6x1 --slab-cells 4 --optics {} --photons 20000 --threads {} "
                          "--json --vtu {}",
                          mpirun(ranks), (dir_ / "optics.toml").string(), ranks == 2 ? 2 : 1, vtu.string())),
        0)
        << err_;
    ASSERT_TRUE(nlohmann::json::accept(out_)) << "not one JSON document:\n" << out_;
    nlohmann::json j = nlohmann::json::parse(out_);
    EXPECT_EQ(j["ranks"], ranks);
    drop_run_facts(j);
    j.erase("vtu");
    if (ranks == 1)
      reference = j;
    else
      EXPECT_EQ(j, reference) << ranks << " ranks";
    EXPECT_TRUE(fs::exists(vtu));
    EXPECT_FALSE(fs::exists(vtu.string() + ".part"));
    if (ranks > 1) {
      EXPECT_EQ(read_file(vtu), read_file(dir_ / "fluence1.vtu")) << ranks << " ranks";
    }
  }
}

TEST_F(MpiCli, StudySweepTableIsTheSameOnOneAndTwoRanks) {
  std::string tables[2];
  for (int ranks : {1, 2}) {
    const auto json = dir_ / fmt::format("study{}.json", ranks);
    ASSERT_EQ(shell(fmt::format("{} study sweep --displacements 0.5 --thickness 1.5 --optics native,cleared "
                                "--photons 15000 --max-edge 1.0 --threads 1 -o {}",
                                mpirun(ranks), json.string())),
              0)
        << err_;
    nlohmann::json j = nlohmann::json::parse(read_file(json));
    ASSERT_GE(j["simulations"].size(), 3u);
    drop_run_facts(j);
    tables[ranks - 1] = j.dump();
  }
  EXPECT_EQ(tables[0], tables[1]);
}

TEST_F(MpiCli, KillingOneRankFailsTheJobAndLeavesNoCompleteOutput) {
  const auto vtu = dir_ / "fluence.vtu";
  const std::string cmd = fmt::format(
      "{} mc --slab 6x6x1 --slab-cells 4 --optics {} --photons 200000000 --threads 1 --json --vtu {} > {} 2> "
      "{}",
      mpirun(2), (dir_ / "optics.toml").string(), vtu.string(), (dir_ / "out").string(),
      (dir_ / "err").string());
  const pid_t job = ::fork();
  ASSERT_GE(job, 0);
  if (job == 0) {
    ::setpgid(0, 0);
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Wait for both ranks to run, then kill one. The ranks are the processes whose command
  // line starts with tocdlab and names this test's folder (mpirun's and the shell's do not).
  const std::string rank_pattern = fmt::format("^{} mc .*{}", TOCDLAB_EXE, dir_.path().string());
  std::string ranks;
  for (int i = 0; i < 200; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const int rc =
        std::system(fmt::format("pgrep -f '{}' > {}", rank_pattern, (dir_ / "pids").string()).c_str());
    ranks = read_file(dir_ / "pids");
    if (rc == 0 && std::count(ranks.begin(), ranks.end(), '\n') >= 2) break;
  }
  std::istringstream pids(ranks);
  pid_t first = 0, second = 0;
  pids >> first >> second;
  ASSERT_GT(second, 0) << "the job's two ranks did not start: " << ranks;
  std::this_thread::sleep_for(std::chrono::seconds(1));  // mid-run
  ASSERT_EQ(::kill(second, SIGKILL), 0);
  // mpirun must notice and end the job (bounded: the run itself would take many minutes).
  int status = 0;
  pid_t done = 0;
  for (int i = 0; i < 300 && done == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    done = ::waitpid(job, &status, WNOHANG);
  }
  if (done == 0) {
    ::kill(-job, SIGKILL);
    ::waitpid(job, &status, 0);
    FAIL() << "mpirun did not end within 30 s of a rank's death";
  }
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_NE(WEXITSTATUS(status), 0);
  EXPECT_FALSE(fs::exists(vtu)) << "a fluence file that looks complete";
  EXPECT_FALSE(nlohmann::json::accept(read_file(dir_ / "out"))) << "a JSON result on stdout";
  bool survivor = true;
  for (int i = 0; i < 20 && survivor; ++i) {  // mpirun ends its other rank as it exits
    survivor = std::system(fmt::format("pgrep -f '{}' > /dev/null", rank_pattern).c_str()) == 0;
    if (survivor) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_FALSE(survivor) << "a rank outlived the job by 2 s";
  std::system(fmt::format("pkill -9 -f '{}'", rank_pattern).c_str());
}

// Streams and exit statuses as docs/cli.md states them: progress on the terminal (stderr) and
// never in the data on stdout; 0 ok, 1 error, 2 usage, every message prefixed "tocdlab: ".
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <poll.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tocd/test/cli.hpp"
#include "tocd/test/temp_dir.hpp"

namespace fs = std::filesystem;
using tocd::test::run_cli;

namespace {

constexpr const char* kOptics = R"([region.1]
mu_a = 0.1
mu_s = 10.0
g = 0.9
n = 1.4
)";

class CliStreams : public ::testing::Test {
 protected:
  void SetUp() override { std::ofstream(dir_ / "optics.toml") << kOptics; }
  /// `tocdlab <args>` is refused: exit `status`, nothing on stdout, stderr opening with `prefix`.
  tocd::test::CliResult expect_refused(const std::string& args, int status, const std::string& prefix) {
    SCOPED_TRACE(args);
    auto r = run_cli(TOCDLAB_EXE, args, dir_);
    EXPECT_EQ(r.status, status) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(r.err.rfind(prefix, 0), 0u) << r.err;
    return r;
  }
  tocd::test::TempDir dir_{"cli_streams"};
};

// Runs tocdlab with stderr on a pseudo-terminal and stdout into `stdout_file`; returns what the
// terminal showed and the exit status.
std::string run_on_terminal(const std::vector<std::string>& args, const fs::path& stdout_file, int& status) {
  int master = -1, slave = -1;
  if (::openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) return "openpty failed";
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int out = ::open(stdout_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, STDOUT_FILENO);
    ::dup2(slave, STDERR_FILENO);
    ::close(master);
    std::vector<char*> argv{const_cast<char*>(TOCDLAB_EXE)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(TOCDLAB_EXE, argv.data());
    ::_exit(127);
  }
  ::close(slave);
  std::string seen;
  char buf[4096];
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  for (;;) {
    pollfd p{master, POLLIN, 0};
    if (::poll(&p, 1, 200) > 0) {
      const ssize_t n = ::read(master, buf, sizeof buf);
      if (n <= 0) break;  // EIO once the child has closed the terminal
      seen.append(buf, static_cast<std::size_t>(n));
    } else if (::waitpid(pid, &status, WNOHANG) == pid) {
      ::close(master);
      return seen;
    }
    if (std::chrono::steady_clock::now() > give_up) ::kill(pid, SIGKILL);
  }
  ::close(master);
  ::waitpid(pid, &status, 0);
  return seen;
}

}  // namespace

TEST_F(CliStreams, ProgressBarOnTheTerminalNeverInTheDataFile) {
  int status = -1;
  const std::string terminal =
      run_on_terminal({"mc", "--slab", "10x10x1", "--slab-cells", "4", "--optics",
                       (dir_ / "optics.toml").string(), "--photons", "20000", "--json"},
                      dir_ / "data.json", status);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << terminal;
  EXPECT_NE(terminal.find("mc ["), std::string::npos) << terminal;
  EXPECT_NE(terminal.find("ETA"), std::string::npos) << terminal;
  EXPECT_NE(terminal.find("20000/20000 photons"), std::string::npos) << terminal;
  const std::string data = tocd::test::read_file(dir_ / "data.json");
  EXPECT_EQ(data.find("ETA"), std::string::npos) << data;
  EXPECT_EQ(data.find('\r'), std::string::npos);
  EXPECT_NO_THROW((void)nlohmann::json::parse(data)) << data;
}

TEST_F(CliStreams, QuietSilencesTheBar) {
  int status = -1;
  const std::string terminal =
      run_on_terminal({"--quiet", "mc", "--slab", "10x10x1", "--slab-cells", "4", "--optics",
                       (dir_ / "optics.toml").string(), "--photons", "2000"},
                      dir_ / "data.txt", status);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << terminal;
  EXPECT_EQ(terminal.find("ETA"), std::string::npos) << terminal;
  EXPECT_NE(tocd::test::read_file(dir_ / "data.txt").find("transmittance"), std::string::npos);
}

TEST_F(CliStreams, UnknownOptionIsAUsageErrorNamingIt) {
  const auto r = expect_refused("mc --bogus", 2, "tocdlab: ");
  EXPECT_NE(r.err.find("--bogus"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("--optics"), std::string::npos) << r.err;
}

TEST_F(CliStreams, UsageErrorsExitTwo) {
  for (const char* args : {"no-such-command", "study paper --photons -5", "mc --slab 1x1x1",
                           "--log-level loud", "predict --photons 1e3x"}) {
    expect_refused(args, 2, "tocdlab: ");
  }
}

TEST_F(CliStreams, BadInputExitsOneNamingIt) {
  const auto missing =
      expect_refused("mc --slab 10x10x1 --optics no-such-optics.toml", 1, "tocdlab: error: ");
  EXPECT_NE(missing.err.find("no-such-optics.toml"), std::string::npos) << missing.err;

  const auto fit = run_cli(TOCDLAB_EXE, "fit --data no-such.csv", dir_);
  EXPECT_EQ(fit.status, 1) << fit.err;
  EXPECT_NE(fit.err.find("no-such.csv"), std::string::npos) << fit.err;
}

TEST_F(CliStreams, HelpAndVersionExitZeroOnStdout) {
  for (const char* args : {"--help", "mc --help", "--version", "-V"}) {
    const auto r = run_cli(TOCDLAB_EXE, args, dir_);
    EXPECT_EQ(r.status, 0) << args;
    EXPECT_FALSE(r.out.empty()) << args;
  }
  EXPECT_NE(run_cli(TOCDLAB_EXE, "mc --help", dir_).out.find("--photons"), std::string::npos);
}

// Load test of the real `tocdlab simlab` process on loopback: 1,000 idle connections, 10
// clients sending a byte every 80 ms and one client that never reads, all at once. A normal
// `tocdlab devices probe` (and the same driver calls in-process, without retries) must still
// succeed within its timeouts, and SIGTERM must stop simlab within 1 s.
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tocd/devices/lab.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/temp_dir.hpp"

extern char** environ;

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

namespace {

constexpr int kIdleConnections = 1000;  // half to each TCP instrument
constexpr int kSlowClients = 10;
constexpr rlim_t kDescriptorsNeeded = 1300;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

/// Starts `args` with stdout and stderr into `log`; returns the pid.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  return rc == 0 ? pid : -1;
}

/// Waits for `pid` at most `limit`; the exit status, or nothing (the process is then killed).
std::optional<int> wait_exit(pid_t pid, std::chrono::milliseconds limit) {
  const auto until = Clock::now() + limit;
  for (;;) {
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
    if (Clock::now() > until) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return std::nullopt;
    }
    std::this_thread::sleep_for(1ms);
  }
}

using tocd::test::read_file;

/// A non-blocking loopback connection (whether or not the server has taken it yet);
/// `receive_buffer` > 0 shrinks its receive buffer first.
int connect_to(int port, int receive_buffer = 0) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (receive_buffer > 0) ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  return fd;
}

/// A client that keeps sending `pattern` a byte every 80 ms, reconnecting when dropped.
struct SlowClient {
  int port;
  std::string pattern;
  int fd = -1;
  std::size_t at = 0;
  int dropped = 0;  ///< times the server closed the connection
  void tick() {
    if (fd < 0) fd = connect_to(port);
    const char b = pattern[at++ % pattern.size()];
    bool closed = ::send(fd, &b, 1, MSG_NOSIGNAL | MSG_DONTWAIT) < 0 && errno != EAGAIN && errno != ENOTCONN;
    char sink[512];
    for (ssize_t n; !closed && (n = ::recv(fd, sink, sizeof sink, MSG_DONTWAIT)) != 0;)
      if (n < 0) {
        closed = errno != EAGAIN && errno != ENOTCONN;
        break;
      }
    if (!closed) return;
    ::close(fd);
    fd = -1;
    ++dropped;
  }
};

/// How many of `fds` have completed their connection (waiting up to 5 s).
int established(const std::vector<int>& fds) {
  int n = 0;
  for (int fd : fds) {
    pollfd p{fd, POLLOUT, 0};
    int error = 0;
    socklen_t len = sizeof error;
    if (::poll(&p, 1, 5000) == 1 && ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &len) == 0 && error == 0)
      ++n;
  }
  return n;
}

/// Idle connections the server has closed (to make room for newer ones).
int closed_by_server(const std::vector<int>& fds) {
  int n = 0;
  for (int fd : fds) {
    char b;
    const ssize_t got = ::recv(fd, &b, 1, MSG_DONTWAIT);
    if (got == 0 || (got < 0 && errno != EAGAIN)) ++n;
  }
  return n;
}

class SimlabUnderLoad : public ::testing::Test {
 protected:
  void SetUp() override {
    rlimit r{};
    ::getrlimit(RLIMIT_NOFILE, &r);
    if (r.rlim_max != RLIM_INFINITY && r.rlim_max < kDescriptorsNeeded)
      GTEST_SKIP() << "the load test needs " << kDescriptorsNeeded << " file descriptors; the hard limit is "
                   << r.rlim_max;
    r.rlim_cur = std::max<rlim_t>(r.rlim_cur, kDescriptorsNeeded);
    ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &r), 0);
    lab_file_ = dir_ / "lab.toml";
    simlab_ = spawn({TOCDLAB_EXE, "simlab", "--sample", "analytic", "--write-config", lab_file_.string()},
                    dir_ / "simlab.log");
    ASSERT_GT(simlab_, 0);
    const auto until = Clock::now() + 20s;
    while (read_file(dir_ / "simlab.log").find("serving until") == std::string::npos) {
      ASSERT_LT(Clock::now(), until) << "simlab did not start:\n" << read_file(dir_ / "simlab.log");
      std::this_thread::sleep_for(20ms);
    }
    lab_ = tocd::devices::load_lab_config(lab_file_.string());
    ASSERT_TRUE(lab_.tester && lab_.power_meter);
  }

  void TearDown() override {
    if (simlab_ > 0 && ::kill(simlab_, 0) == 0) {
      ::kill(simlab_, SIGKILL);
      ::waitpid(simlab_, nullptr, 0);
    }
  }

  // `tocdlab devices probe` itself, as a user runs it: the worst of three, process start included.
  double worst_probe_run_ms() {
    double worst = 0;
    for (int i = 0; i < 3; ++i) {
      const auto t0 = Clock::now();
      const pid_t probe =
          spawn({TOCDLAB_EXE, "devices", "probe", "--lab", lab_file_.string()}, dir_ / "probe.log");
      EXPECT_GT(probe, 0);
      if (probe <= 0) return HUGE_VAL;
      const auto rc = wait_exit(probe, 20s);
      worst = std::max(worst, ms_since(t0));
      EXPECT_TRUE(rc.has_value()) << "probe hung";
      if (!rc) return HUGE_VAL;
      EXPECT_EQ(*rc, 0) << read_file(dir_ / "probe.log");
    }
    return worst;
  }

  tocd::test::TempDir dir_{"simlab_load"};
  fs::path lab_file_;
  pid_t simlab_ = -1;
  tocd::devices::LabConfig lab_;
};

// The clients that press on the simulated lab's limits, each on a thread of its own; the load
// ends however the test leaves (a failed assertion or an exception included).
struct Load {
  std::atomic<bool> done{false};
  std::atomic<int> slow_dropped{0}, deaf_dropped{0};
  std::vector<std::thread> threads;

  // Slow-byte clients: Modbus read requests to the tester, an endless line to the meter.
  void start_slow_clients(int tester_port, int meter_port) {
    threads.emplace_back([this, tester_port, meter_port] {
      const std::string modbus_read("\0\1\0\0\0\6\1\4\0\0\0\6", 12);
      std::vector<SlowClient> clients;
      for (int i = 0; i < kSlowClients; ++i)
        clients.push_back(i % 2 ? SlowClient{meter_port, "MEAS?;MEAS?;MEAS?"}
                                : SlowClient{tester_port, modbus_read});
      while (!done) {
        for (auto& c : clients) c.tick();
        std::this_thread::sleep_for(80ms);
      }
      for (auto& c : clients) {
        ::close(c.fd);
        slow_dropped += c.dropped;
      }
    });
  }
  // A meter client that sends queries and never reads an answer (reconnecting when dropped).
  void start_deaf_client(int meter_port) {
    threads.emplace_back([this, meter_port] {
      std::string burst;
      for (int i = 0; i < 100; ++i) burst += "*IDN?\n";
      int fd = -1;
      while (!done) {
        if (fd < 0) fd = connect_to(meter_port, 4096);
        if (::send(fd, burst.data(), burst.size(), MSG_NOSIGNAL | MSG_DONTWAIT) < 0 && errno != EAGAIN &&
            errno != ENOTCONN) {
          ::close(fd);
          fd = -1;
          ++deaf_dropped;
        }
        std::this_thread::sleep_for(2ms);
      }
      ::close(fd);
    });
  }
  void stop() {
    done = true;
    for (auto& t : threads)
      if (t.joinable()) t.join();
  }
  ~Load() { stop(); }
};

// The same driver calls as `devices probe`, in-process, without retries (any stall is an
// error): the worst tester read and meter reading of ten, in ms.
std::pair<double, double> worst_driver_calls_ms(const tocd::devices::LabConfig& lab) {
  tocd::devices::LabConfig no_retries;
  no_retries.tester = lab.tester;
  no_retries.tester->link.retries = 0;
  no_retries.power_meter = lab.power_meter;
  no_retries.power_meter->retries = 0;
  double worst_tester_ms = 0, worst_meter_ms = 0;
  auto rig = tocd::devices::open_lab(no_retries);
  for (int i = 0; i < 10; ++i) {
    auto t0 = Clock::now();
    EXPECT_NO_THROW(rig.tester->read());
    worst_tester_ms = std::max(worst_tester_ms, ms_since(t0));
    t0 = Clock::now();
    EXPECT_NO_THROW(rig.power_meter->measure());
    worst_meter_ms = std::max(worst_meter_ms, ms_since(t0));
  }
  return {worst_tester_ms, worst_meter_ms};
}

}  // namespace

TEST_F(SimlabUnderLoad, ProbeSucceedsAndSigtermStopsWithinOneSecond) {
  const int tester_port = lab_.tester->address.port;
  const int meter_port = lab_.power_meter->port;

  // In bursts of 50 with short pauses, so that the kernel's accept queue never overflows into
  // SYN retries (which would only slow the test down).
  std::vector<int> idle;
  for (int i = 0; i < kIdleConnections; ++i) {
    idle.push_back(connect_to(i % 2 ? meter_port : tester_port));
    if (i % 50 == 49) std::this_thread::sleep_for(10ms);
  }
  ASSERT_EQ(established(idle), kIdleConnections);

  Load load;
  load.start_slow_clients(tester_port, meter_port);
  load.start_deaf_client(meter_port);
  // Long enough for the endless lines to pass the 2 s request deadline: the load is on.
  std::this_thread::sleep_for(2500ms);

  const auto [worst_tester_ms, worst_meter_ms] = worst_driver_calls_ms(lab_);
  const double worst_probe_ms = worst_probe_run_ms();
  const int displaced = closed_by_server(idle);
  const auto t0 = Clock::now();
  ASSERT_EQ(::kill(simlab_, SIGTERM), 0);
  const auto rc = wait_exit(simlab_, 5s);
  const double stop_ms = ms_since(t0);
  simlab_ = -1;
  load.stop();
  for (int fd : idle) ::close(fd);

  std::printf(
      "under load: tester read worst %.1f ms, meter reading worst %.1f ms, `devices probe` worst %.0f ms "
      "(process start included); %d idle connections displaced, slow clients dropped %d times, the deaf "
      "client %d times; SIGTERM to exit %.1f ms\n",
      worst_tester_ms, worst_meter_ms, worst_probe_ms, displaced, load.slow_dropped.load(),
      load.deaf_dropped.load(), stop_ms);
  ASSERT_TRUE(rc.has_value()) << "simlab ignored SIGTERM for 5 s";
  EXPECT_EQ(*rc, 0);
  EXPECT_LT(stop_ms, 1000.0);
  // Timeouts of the lab config: tester 0.5 s, meter 1 s; no retry was needed above.
  EXPECT_LT(worst_tester_ms, 500.0);
  EXPECT_LT(worst_meter_ms, 1000.0);
  EXPECT_LT(worst_probe_ms, 5000.0);
  // The load really pressed on every limit: idle connections beyond 2 x 256 made room for newer
  // ones, endless lines passed the deadline, the deaf client's backlog passed its cap.
  EXPECT_GE(displaced, kIdleConnections - 2 * 256);
  EXPECT_GT(load.slow_dropped.load(), 0);
  EXPECT_GT(load.deaf_dropped.load(), 0);
}

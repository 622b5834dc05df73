// Kill test: a child process records samples continuously through a Writer (default options:
// batch interval 0.1 s) and is killed with SIGKILL mid-run. Reopening the file must show an
// intact database (integrity_check ok), the run marked interrupted, and every sample the child
// enqueued more than 0.5 s before the kill (the bound docs/database.md states).
#include <cstdint>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tocd/core/clock.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/writer.hpp"
#include "tocd/test/temp_dir.hpp"

namespace {

using namespace tocd::db;
using tocd::test::TempDir;

constexpr std::int64_t kBoundNs = 500'000'000;  // 0.5 s

// What the child tells the parent (one atomic pipe write each).
struct Report {
  std::int64_t committed;   // samples the writer has committed (FIFO: indices 0..committed-1)
  std::int64_t last_index;  // last sample index enqueued
  std::int64_t last_t_ns;   // its timestamp
};

[[noreturn]] void child(const std::filesystem::path& path, int out_fd) {
  try {
    Database db(path);
    const auto run = db.create_run({}).id;
    const auto ch = db.add_channel({0, run, "load", "N", 0, 50000.0});
    StepRecord st;
    st.run_id = run;
    st.index = 0;
    st.settled_t_ns = tocd::monotonic_ns();
    db.add_step(st);
    Writer w(db);  // default options: what `tocdlab run` uses
    for (std::int64_t i = 0;; ++i) {
      const auto t = tocd::monotonic_ns();
      w.enqueue(Sample{ch.id, t, static_cast<double>(i)});
      if (i % 100 == 99) {  // about 50,000 samples/s
        const Report r{static_cast<std::int64_t>(w.stats().written), i, t};
        if (::write(out_fd, &r, sizeof r) != sizeof r) ::_exit(3);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
    }
  } catch (...) {
    ::_exit(2);
  }
}

TEST(DbKill, SigkillMidRunLosesNothingOlderThanTheBound) {
  const TempDir dir("db_kill");
  const auto path = dir / "lab.sqlite";
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::close(fds[0]);
    child(path, fds[1]);
  }
  ::close(fds[1]);

  std::vector<Report> reports;
  Report r{};
  // Wait until several batches are committed, then keep going a little: kill lands mid-batch.
  while (::read(fds[0], &r, sizeof r) == sizeof r) {
    reports.push_back(r);
    if (r.committed >= 20000 && reports.size() > 300) break;
  }
  ASSERT_FALSE(reports.empty()) << "the child reported nothing";
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  const auto t_kill = tocd::monotonic_ns();
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "child exited on its own with status " << WEXITSTATUS(status);
  while (::read(fds[0], &r, sizeof r) == sizeof r) reports.push_back(r);
  ::close(fds[0]);

  // A read-only Reader opened first (before anything marks the run) already sees every
  // committed batch: the WAL left by the killed process is recovered without a writer.
  std::int64_t seen_by_first_reader = 0;
  {
    Reader first(path);
    const auto runs = first.runs();
    ASSERT_EQ(runs.size(), 1u);
    EXPECT_EQ(runs[0].run.status, RunStatus::running);  // not yet marked: readers never write
    EXPECT_FALSE(runs[0].live);                         // but nobody holds its lock
    seen_by_first_reader = first.sample_count(first.channels(runs[0].run.id).at(0).id);
    EXPECT_GE(seen_by_first_reader, reports.back().committed);
  }

  Database db(path);
  EXPECT_EQ(db.integrity_check(), "ok");
  ASSERT_EQ(db.interrupted_on_open().size(), 1u);
  const auto run = db.interrupted_on_open()[0];
  Reader rd(path);
  EXPECT_EQ(rd.run(run).status, RunStatus::interrupted);
  const auto ch = rd.channel(run, "load");
  ASSERT_TRUE(ch.has_value());
  const auto samples = rd.samples(ch->id);

  // What is there is a gap-free prefix of what was enqueued.
  for (std::size_t i = 0; i < samples.size(); ++i) {
    ASSERT_EQ(samples[i].value, static_cast<double>(i)) << "sample " << i << " missing or out of order";
    if (i) {
      ASSERT_GT(samples[i].t_ns, samples[i - 1].t_ns);
    }
  }
  const auto stored = static_cast<std::int64_t>(samples.size());
  EXPECT_EQ(stored, seen_by_first_reader);
  // Everything the writer reported committed is there.
  EXPECT_GE(stored, reports.back().committed);
  // Everything enqueued more than 0.5 s before the kill is there.
  std::int64_t must_have = -1;
  for (const auto& rep : reports)
    if (rep.last_t_ns < t_kill - kBoundNs) must_have = std::max(must_have, rep.last_index);
  ASSERT_GE(must_have, 0);
  EXPECT_GT(stored, must_have) << "lost samples enqueued more than 0.5 s before the kill";
  std::cout << "[ kill    ] " << stored << " samples stored, " << reports.back().last_index + 1
            << " enqueued by the last report; newest stored sample "
            << static_cast<double>(t_kill - samples.back().t_ns) * 1e-9 << " s before the kill\n";

  // The interrupted run resumes after its completed step 0.
  const auto p = db.resume_run(run);
  EXPECT_EQ(p.first_incomplete_step, 1);
  EXPECT_EQ(p.gap_from_t_ns, samples.back().t_ns);
}

}  // namespace

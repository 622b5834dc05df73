// The background writer: everything enqueued is committed in order, counters add up, the
// queue bound drops (and counts) what does not fit, unknown channels are rejected, not lost.
#include <cmath>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_database.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/writer.hpp"

namespace {

using namespace tocd::db;
using tocd::db::testing::OpenDatabaseTest;
using tocd::db::testing::run_with_channel;

class DbWriter : public OpenDatabaseTest {};

TEST_F(DbWriter, SamplesFromManyThreadsAreAllCommitted) {
  const auto run = db_.create_run({}).id;
  constexpr int kThreads = 4, kPerThread = 20000;
  std::vector<Channel> ch;
  for (int i = 0; i < kThreads; ++i)
    ch.push_back(db_.add_channel({0, run, "ch" + std::to_string(i), "V", 0, kUnset}));
  Writer w(db_, {.batch_interval = std::chrono::milliseconds(20),
                 .batch_rows = 5000,
                 .queue_capacity = 1'000'000,
                 .on_failure = {}});
  std::vector<std::thread> producers;
  for (int i = 0; i < kThreads; ++i) {
    producers.emplace_back([&, i] {
      for (int k = 0; k < kPerThread; ++k) {
        if (k % 100 == 0) {  // a mix of single and span enqueues
          std::vector<Sample> block;
          for (int j = 0; j < 100; ++j) block.push_back({ch[i].id, k + j, (k + j) * 0.5 + i});
          w.enqueue(block);
          k += 99;
        } else {
          w.enqueue(Sample{ch[i].id, k, k * 0.5 + i});
        }
      }
    });
  }
  for (auto& t : producers) t.join();
  w.enqueue(EventRecord{0, run, 5, "operator", "note from the bench", -1, ""});
  w.flush();
  const WriterStats s = w.stats();
  EXPECT_EQ(s.enqueued, kThreads * kPerThread + 1u);
  EXPECT_EQ(s.written, s.enqueued);
  EXPECT_EQ(s.dropped, 0u);
  EXPECT_EQ(s.rejected, 0u);
  EXPECT_EQ(s.failed, 0u);
  EXPECT_EQ(s.queue_depth, 0u);
  EXPECT_GT(s.batches, 0u);
  EXPECT_EQ(s.last_error, "");

  Reader rd(path_);
  for (int i = 0; i < kThreads; ++i) {
    const auto got = rd.samples(ch[i].id);
    ASSERT_EQ(got.size(), static_cast<std::size_t>(kPerThread));
    for (int k = 0; k < kPerThread; ++k) {
      ASSERT_EQ(got[k].t_ns, k);
      ASSERT_EQ(got[k].value, k * 0.5 + i);
    }
  }
  EXPECT_EQ(rd.events(run).size(), 1u);
}

TEST_F(DbWriter, BatchIntervalCommitsWithoutFlush) {
  const Channel ch = run_with_channel(db_, "load", "N");
  Writer w(db_, {.batch_interval = std::chrono::milliseconds(10),
                 .batch_rows = 1'000'000,
                 .queue_capacity = 1'000'000,
                 .on_failure = {}});
  w.enqueue(Sample{ch.id, 1, 1.0});
  Reader rd(path_);
  // Not a timing assertion: wait (up to 10 s) until the interval commit shows.
  for (int i = 0; i < 1000 && rd.sample_count(ch.id) == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(rd.sample_count(ch.id), 1);
  w.flush();  // the counters are updated just after the commit becomes visible
  EXPECT_EQ(w.stats().batches, 1u);
}

// The run's own writes (its steps and events, on the Database's connection) get in between the
// background writer's batches while it works through a backlog. SQLite's write lock is not
// fair: a writer committing batch after batch takes it again microseconds after each commit,
// and the other connection's busy handler, polling every 100 ms, missed every gap until the
// backlog was done or its 10 s timeout ran out ("database is locked" from add_step, in the kill
// test's resumed run under the sanitizers). Not a timing assertion: the order is what is checked
// (the backlog is forty batches; each write must get in within three of them; without the turns,
// the writes here waited for 22 to 40).
TEST_F(DbWriter, TheRunsOwnWritesGetInBetweenTheBatchesOfABacklog) {
  const Channel ch = run_with_channel(db_, "load", "N");
  constexpr std::size_t kBatch = 5000, kBatches = 40, kRows = kBatch * kBatches;
  Writer w(db_, {.batch_interval = std::chrono::milliseconds(1),
                 .batch_rows = kBatch,
                 .queue_capacity = kRows,
                 .on_failure = {}});
  std::vector<Sample> backlog;
  for (std::size_t i = 0; i < kRows; ++i) backlog.push_back({ch.id, static_cast<std::int64_t>(i), 1.0});
  ASSERT_EQ(w.enqueue(backlog), kRows);
  for (int i = 0; i < 10000 && w.stats().batches == 0; ++i)  // the writer is into the backlog
    std::this_thread::sleep_for(std::chrono::milliseconds(1));

  // Each write may wait for the batch being written, and the counter may lag one commit.
  const auto before_event = w.stats().written;
  db_.add_event(EventRecord{0, ch.run_id, 1, "operator", "a note while the backlog is written", -1, ""});
  const auto after_event = w.stats().written;
  StepRecord step;
  step.run_id = ch.run_id;
  step.target_displacement_mm = 0.25;
  db_.add_step(step);  // BEGIN IMMEDIATE, as in the kill test
  const auto after_step = w.stats().written;
  EXPECT_LE(after_event - before_event, 3 * kBatch) << "the event waited for the backlog";
  EXPECT_LE(after_step - after_event, 3 * kBatch) << "the step waited for the backlog";

  w.flush();
  EXPECT_EQ(w.stats().written, kRows);
  EXPECT_EQ(w.stats().failed, 0u);
  const Reader rd(path_);
  EXPECT_EQ(rd.sample_count(ch.id), static_cast<std::int64_t>(kRows));
  EXPECT_EQ(rd.steps(ch.run_id).size(), 1u);
}

TEST_F(DbWriter, NanValuesSurviveAsNan) {
  const Channel ch = run_with_channel(db_, "power", "W");
  {
    Writer w(db_);
    w.enqueue(Sample{ch.id, 1, std::nan("")});  // an over-range reading
    w.enqueue(Sample{ch.id, 2, -0.0});
  }  // the destructor flushes
  const auto got = Reader(path_).samples(ch.id);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_TRUE(std::isnan(got[0].value));
  EXPECT_EQ(got[1].value, 0.0);
}

TEST_F(DbWriter, FullQueueDropsAndCountsNeverBlocks) {
  const Channel ch = run_with_channel(db_, "load", "N");
  // A long interval and a huge batch size: nothing leaves the queue before the flush.
  Writer w(db_, {.batch_interval = std::chrono::milliseconds(60'000),
                 .batch_rows = 1'000'000,
                 .queue_capacity = 100,
                 .on_failure = {}});
  std::vector<Sample> block(150, Sample{ch.id, 0, 1.0});
  EXPECT_EQ(w.enqueue(block), 100u);
  EXPECT_FALSE(w.enqueue(Sample{ch.id, 1, 1.0}));
  auto s = w.stats();
  EXPECT_EQ(s.enqueued, 100u);
  EXPECT_EQ(s.dropped, 51u);
  EXPECT_EQ(s.queue_high_water, 100u);
  w.flush();
  s = w.stats();
  EXPECT_EQ(s.written, 100u);
  EXPECT_TRUE(w.enqueue(Sample{ch.id, 2, 1.0}));  // room again
  w.stop();
  EXPECT_FALSE(w.enqueue(Sample{ch.id, 3, 1.0}));  // stopped: dropped, counted
  EXPECT_EQ(w.stats().written, 101u);
  EXPECT_EQ(w.stats().dropped, 52u);
}

TEST_F(DbWriter, UnknownChannelIsRejectedOthersKept) {
  const Channel ch = run_with_channel(db_, "load", "N");
  Writer w(db_);
  w.enqueue(Sample{ch.id, 1, 1.0});
  w.enqueue(Sample{424242, 2, 2.0});
  w.enqueue(EventRecord{0, 999, 3, "fault", "no such run", -1, ""});
  w.flush();
  const auto s = w.stats();
  EXPECT_EQ(s.written, 1u);
  EXPECT_EQ(s.rejected, 2u);
  EXPECT_THAT(s.last_error, ::testing::HasSubstr("unknown"));
  // A channel added after the writer started is found.
  const auto late = db_.add_channel({0, ch.run_id, "late", "N", 0, kUnset});
  w.enqueue(Sample{late.id, 4, 4.0});
  w.flush();
  EXPECT_EQ(w.stats().written, 2u);
}

}  // namespace

// Readers and writers at the same time: a Reader sees exactly what is committed while the
// Writer keeps writing, neither side ever fails with SQLITE_BUSY, and decimation is right.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "test_database.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/writer.hpp"

namespace {

using namespace tocd::db;
using tocd::db::testing::OpenDatabaseTest;
using tocd::db::testing::run_with_channel;
using tocd::db::testing::TestDatabase;

class DbConcurrency : public OpenDatabaseTest {};

TEST_F(DbConcurrency, ReadersSeeCommittedPrefixesWhileTheWriterWrites) {
  const Channel ch = run_with_channel(db_, "load", "N", 1000.0);
  const auto run = ch.run_id;
  Writer w(db_, {.batch_interval = std::chrono::milliseconds(5),
                 .batch_rows = 2000,
                 .queue_capacity = 1'000'000,
                 .on_failure = {}});

  // Background readers hammer the file the whole time; any error (SQLITE_BUSY included) or a
  // non-prefix view fails the test.
  std::atomic<bool> done{false};
  std::atomic<int> reader_errors{0}, views{0};
  std::vector<std::thread> readers;
  for (int r = 0; r < 2; ++r) {
    readers.emplace_back([&] {
      try {
        Reader rd(path_);
        std::size_t last = 0;
        while (!done.load()) {
          const auto got = rd.samples(ch.id);
          bool prefix = got.size() >= last;
          for (std::size_t i = 0; prefix && i < got.size(); ++i)
            prefix = got[i].t_ns == static_cast<std::int64_t>(i);
          if (!prefix) ++reader_errors;
          last = got.size();
          rd.runs();
          rd.compare(run);
          ++views;
        }
      } catch (const std::exception&) {
        ++reader_errors;
      }
    });
  }

  Reader rd(path_);
  std::int64_t total = 0;
  for (int chunk = 0; chunk < 40; ++chunk) {
    std::vector<Sample> block;
    for (int k = 0; k < 2500; ++k, ++total) block.push_back({ch.id, total, static_cast<double>(total)});
    ASSERT_EQ(w.enqueue(block), block.size());
    // Lifecycle writes on the other connection interleave with the writer's batches.
    db_.add_event({0, run, total, "step", "chunk " + std::to_string(chunk), chunk, ""});
    StepRecord st;
    st.run_id = run;
    st.index = chunk;
    st.channels = {{ch.id, 1.0, 0.0, 2500}};
    db_.add_step(st);
    w.flush();
    ASSERT_EQ(rd.sample_count(ch.id), total);  // committed = visible, while the writer runs on
  }
  done = true;
  for (auto& t : readers) t.join();
  EXPECT_EQ(reader_errors.load(), 0);
  EXPECT_GT(views.load(), 0);
  EXPECT_EQ(w.stats().written, static_cast<std::uint64_t>(total));
  EXPECT_EQ(rd.steps(run).size(), 40u);
  EXPECT_EQ(db_.integrity_check(), "ok");
}

class DbDecimation : public ::testing::Test {
 protected:
  void SetUp() override {
    db_ = std::make_unique<Database>(dir_.location());
    ch_ = run_with_channel(*db_, "load", "N").id;
    Writer w(*db_);
    for (int i = 0; i < kN; ++i) w.enqueue(Sample{ch_, 1000 + 10 * i, value(i)});
  }
  static double value(int i) { return std::sin(0.01 * i) + (i == 4321 ? 50.0 : 0.0); }  // one spike
  // All of the channel, decimated to at most `max_points` by `decimation`, as a reader reads it.
  std::vector<Sample> decimated(Decimation decimation, std::size_t max_points) const {
    SampleQuery q;
    q.decimation = decimation;
    q.max_points = max_points;
    return Reader(dir_.location()).samples(ch_, q);
  }
  static constexpr int kN = 10000;
  TestDatabase dir_;
  std::unique_ptr<Database> db_;
  std::int64_t ch_ = 0;
};

TEST_F(DbDecimation, TimeRangeIsInclusive) {
  Reader rd(dir_.location());
  SampleQuery q;
  q.from_t_ns = 1000 + 10 * 100;
  q.to_t_ns = 1000 + 10 * 199;
  const auto got = rd.samples(ch_, q);
  ASSERT_EQ(got.size(), 100u);
  EXPECT_EQ(got.front().t_ns, q.from_t_ns);
  EXPECT_EQ(got.back().t_ns, q.to_t_ns);
  EXPECT_EQ(rd.sample_count(ch_, q), 100);
  EXPECT_EQ(rd.sample_count(ch_), kN);
}

TEST_F(DbDecimation, MeanBucketsMatchADirectComputation) {
  const auto got = decimated(Decimation::mean, 100);
  ASSERT_LE(got.size(), 100u);
  ASSERT_GE(got.size(), 90u);
  // Same buckets computed here: width = span / buckets + 1 over [t_min, t_max].
  const std::int64_t t0 = 1000, span = 10 * (kN - 1), width = span / 100 + 1;
  std::vector<double> sum(101, 0.0), tsum(101, 0.0);
  std::vector<int> n(101, 0);
  for (int i = 0; i < kN; ++i) {
    const auto b = static_cast<std::size_t>((10 * i) / width);
    sum[b] += value(i);
    tsum[b] += 10.0 * i;
    ++n[b];
  }
  std::size_t k = 0;
  for (std::size_t b = 0; b < sum.size(); ++b) {
    if (n[b] == 0) continue;
    ASSERT_LT(k, got.size());
    EXPECT_NEAR(got[k].value, sum[b] / n[b], 1e-12);
    EXPECT_NEAR(static_cast<double>(got[k].t_ns), t0 + tsum[b] / n[b], 1.0);
    ++k;
  }
  EXPECT_EQ(k, got.size());
}

TEST_F(DbDecimation, MinMaxKeepsTheSpikeAndTheRange) {
  const auto got = decimated(Decimation::min_max, 200);
  ASSERT_LE(got.size(), 200u);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int i = 0; i < kN; ++i) {
    lo = std::min(lo, value(i));
    hi = std::max(hi, value(i));
  }
  double glo = lo + 1, ghi = hi - 1;
  bool spike_at_its_time = false;
  for (std::size_t i = 0; i < got.size(); ++i) {
    glo = std::min(glo, got[i].value);
    ghi = std::max(ghi, got[i].value);
    if (got[i].value == value(4321)) spike_at_its_time = got[i].t_ns == 1000 + 10 * 4321;
    if (i) {
      EXPECT_LE(got[i - 1].t_ns, got[i].t_ns);
    }
  }
  EXPECT_EQ(glo, lo);
  EXPECT_EQ(ghi, hi);
  EXPECT_TRUE(spike_at_its_time);
  // Fewer samples than max_points: returned as they are.
  EXPECT_EQ(decimated(Decimation::min_max, 1'000'000).size(), static_cast<std::size_t>(kN));
}

}  // namespace

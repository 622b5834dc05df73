// A run whose clock runs faster than real time (the simulated lab at --clock-factor F): the
// samples keep the run's clock in t_ns, and every UTC the database gives (the records, the
// sample_series view, the export) is real time, ordered, within the run's start and end.
#include <cmath>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include "raw_sqlite.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/writer.hpp"
#include "tocd/test/temp_dir.hpp"

namespace {

using namespace tocd::db;
using tocd::test::TempDir;

constexpr double kFactor = 10.0;
constexpr std::int64_t kSecond = 1'000'000'000LL;

// The view's columns for every sample of `run`, ordered by t_ns.
struct SeriesRow {
  std::int64_t t_ns = 0, utc_ns = 0;
  double t_s = 0, clock_s = 0, clock_factor = 0;
};
std::vector<SeriesRow> series(const std::filesystem::path& path, std::int64_t run) {
  std::vector<SeriesRow> out;
  const std::string sql = fmt::format(
      "SELECT t_ns, utc_ns, t_s, clock_s, clock_factor FROM sample_series WHERE run_id = {} ORDER BY t_ns",
      run);
  tocd::db::testing::raw_for_each_row(path, sql, [&](sqlite3_stmt* s) {
    out.push_back({sqlite3_column_int64(s, 0), sqlite3_column_int64(s, 1), sqlite3_column_double(s, 2),
                   sqlite3_column_double(s, 3), sqlite3_column_double(s, 4)});
  });
  return out;
}

// A run in `db` whose clock runs kFactor times faster than real time, and its power channel.
struct FastRun {
  RunRecord run;
  Channel power;
};
FastRun fast_run(Database& db) {
  NewRun nr;
  nr.clock_factor = kFactor;
  const RunRecord run = db.create_run(nr);
  return {run, db.add_channel({0, run.id, "power", "W", 0, 10.0})};
}

TEST(DbClockFactor, UtcIsRealTimeAndTheRunClockIsItsOwnColumn) {
  const TempDir dir("db_clock");
  const auto path = dir / "lab.sqlite";
  Database db(path);
  const auto [run, power] = fast_run(db);
  EXPECT_DOUBLE_EQ(run.clock_factor, kFactor);
  // 20 s on the run's clock, one sample a second: 2 s of real time at factor 10.
  {
    Writer w(db);
    for (int i = 0; i <= 20; ++i) w.enqueue(Sample{power.id, run.monotonic_anchor_ns + i * kSecond, 1e-3});
  }
  const auto rows = series(path, run.id);
  ASSERT_EQ(rows.size(), 21u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto k = static_cast<std::int64_t>(i);
    // Independent of the code under test: real time = wall anchor + run-clock time / factor.
    EXPECT_EQ(rows[i].utc_ns, run.wall_anchor_utc_ns + k * kSecond / 10) << "sample " << i;
    EXPECT_NEAR(rows[i].t_s, 0.1 * k, 1e-9) << "sample " << i;
    EXPECT_NEAR(rows[i].clock_s, 1.0 * k, 1e-9) << "sample " << i;
    EXPECT_DOUBLE_EQ(rows[i].clock_factor, kFactor);
  }
  const Reader reader(path);
  const auto anchors = reader.anchors(run.id);
  ASSERT_EQ(anchors.size(), 1u);
  EXPECT_DOUBLE_EQ(anchors[0].clock_factor, kFactor);
  EXPECT_EQ(utc_ns(anchors, 0, run.monotonic_anchor_ns + 20 * kSecond), run.wall_anchor_utc_ns + 2 * kSecond);
  EXPECT_EQ(reader.run(run.id).to_utc_ns(run.monotonic_anchor_ns + 5 * kSecond),
            run.wall_anchor_utc_ns + kSecond / 2);
}

TEST(DbClockFactor, AResumedFastRunKeepsItsSamplesOrderedAndItsUtcReal) {
  const TempDir dir("db_clock");
  const auto path = dir / "lab.sqlite";
  Database db(path);
  const auto [run, power] = fast_run(db);
  // 30 s on the run's clock (3 s of real time at factor 10) recorded within a few real ms:
  // the run clock is now well ahead of the monotonic clock.
  const std::int64_t last = run.monotonic_anchor_ns + 30 * kSecond;
  {
    Writer w(db);
    w.enqueue(Sample{power.id, last, 1e-3});
  }
  db.set_run_status(run.id, RunStatus::interrupted);
  const ResumePoint p = db.resume_run(run.id, kFactor);
  // The resumed segment starts after everything recorded: t_ns stays ordered.
  EXPECT_GT(p.gap_to_t_ns, last);
  EXPECT_EQ(p.gap_from_t_ns, last);
  EXPECT_EQ(p.gap_event.t_ns, p.gap_to_t_ns);
  EXPECT_EQ(p.gap_event.message.find("restarted"), std::string::npos) << p.gap_event.message;
  {
    Writer w(db);
    w.enqueue(Sample{power.id, p.gap_to_t_ns + kSecond, 2e-3});
  }
  db.set_run_status(run.id, RunStatus::completed);
  const Reader reader(path);
  const auto anchors = reader.anchors(run.id);
  ASSERT_EQ(anchors.size(), 2u);
  EXPECT_EQ(anchors[1].monotonic_ns, p.gap_to_t_ns);
  EXPECT_DOUBLE_EQ(anchors[1].clock_factor, kFactor);
  const auto rows = series(path, run.id);
  ASSERT_EQ(rows.size(), 2u);
  // The resumed sample's UTC is its segment's anchor plus 1 s / 10 of real time.
  EXPECT_EQ(rows[1].utc_ns, anchors[1].wall_utc_ns + kSecond / 10);
  const auto end = reader.run(run.id).ended_utc_ns;
  ASSERT_TRUE(end.has_value());
  // The run ended right after the resumed sample was written, well before its UTC would be
  // with the clock taken as real time (30 s after the first anchor).
  EXPECT_LT(*end, run.wall_anchor_utc_ns + 30 * kSecond);
  EXPECT_GE(rows[0].utc_ns, run.started_utc_ns);
  EXPECT_EQ(rows[0].utc_ns, run.wall_anchor_utc_ns + 3 * kSecond);
}

TEST(DbClockFactor, AClockFactorThatIsNoPositiveNumberIsRefused) {
  const TempDir dir("db_clock");
  Database db(dir / "lab.sqlite");
  for (const double bad : {0.0, -2.0, std::nan("")}) {
    NewRun nr;
    nr.clock_factor = bad;
    EXPECT_THROW(db.create_run(nr), DatabaseError) << bad;
  }
  const auto run = db.create_run({}).id;
  db.set_run_status(run, RunStatus::aborted);
  EXPECT_THROW(db.resume_run(run, 0.0), DatabaseError);
}

}  // namespace

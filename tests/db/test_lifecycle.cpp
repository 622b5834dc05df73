// Run lifecycle: runs left running by a gone process become interrupted on open, live runs are
// left alone, and an interrupted run resumes at its first incomplete step with a gap event.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_database.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"

namespace {

using namespace tocd::db;
using ::testing::HasSubstr;
using tocd::db::testing::TestDatabase;

StepRecord completed_step(std::int64_t run, int index, std::int64_t t_ns) {
  StepRecord s;
  s.run_id = run;
  s.index = index;
  s.settled_t_ns = t_ns;
  s.recorded_from_t_ns = t_ns;
  s.recorded_to_t_ns = t_ns + 1000;
  s.measured_transmission = 0.5;
  return s;
}

TEST(DbLifecycle, RunLeftRunningByAClosedDatabaseIsInterruptedOnOpen) {
  TestDatabase dir;
  const auto path = dir.location();
  std::int64_t left = 0, done = 0;
  const auto t = tocd::monotonic_ns();
  {
    Database db(path);
    left = db.create_run({}).id;
    done = db.create_run({}).id;
    db.add_event({0, left, t, "state", "running", -1, ""});
    db.set_run_status(done, RunStatus::completed);
    // Closing without a final status is what a crash looks like to the file.
  }
  Database db(path);
  EXPECT_EQ(db.interrupted_on_open(), std::vector<std::int64_t>{left});
  Reader rd(path);
  const RunRecord r = rd.run(left);
  EXPECT_EQ(r.status, RunStatus::interrupted);
  ASSERT_TRUE(r.ended_utc_ns.has_value());
  EXPECT_EQ(*r.ended_utc_ns, r.to_utc_ns(t));  // ended at the last recorded time
  EXPECT_EQ(rd.run(done).status, RunStatus::completed);
  const auto events = rd.events(left);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[1].kind, "state");
  EXPECT_THAT(events[1].message, HasSubstr("interrupted"));
  EXPECT_EQ(db.integrity_check(), "ok");
  // A second open finds nothing more to mark.
  EXPECT_TRUE(Database(path).interrupted_on_open().empty());
}

TEST(DbLifecycle, RunRecordingInALiveDatabaseIsNotMarked) {
  TestDatabase dir;
  const auto path = dir.location();
  Database recorder(path);
  const auto run = recorder.create_run({}).id;
  EXPECT_TRUE(recorder.is_live(run));
  // A second open (e.g. `tocdlab runs` in another terminal) while the run records.
  Database other(path);
  EXPECT_TRUE(other.interrupted_on_open().empty());
  EXPECT_TRUE(other.is_live(run));
  EXPECT_EQ(other.run(run).status, RunStatus::running);
  EXPECT_TRUE(Reader(path).is_live(run));
  EXPECT_THROW(other.resume_run(run), DatabaseError);
  recorder.set_run_status(run, RunStatus::completed);
  EXPECT_FALSE(other.is_live(run));
  EXPECT_FALSE(Reader(path).runs()[0].live);
}

TEST(DbLifecycle, InterruptedRunResumesAtFirstIncompleteStepWithAGapEvent) {
  TestDatabase dir;
  const auto path = dir.location();
  std::int64_t run = 0;
  const auto t0 = tocd::monotonic_ns();
  {
    Database db(path);
    run = db.create_run({}).id;
    db.add_step(completed_step(run, 0, t0));
    db.add_step(completed_step(run, 1, t0 + 2000));
    StepRecord cut = completed_step(run, 2, t0 + 4000);
    cut.completed = false;
    db.add_step(cut);
    db.add_step(completed_step(run, 3, t0 + 6000));  // out of order: does not count
  }
  Database db(path);
  ASSERT_EQ(db.run(run).status, RunStatus::interrupted);
  EXPECT_EQ(db.first_incomplete_step(run), 2);
  const ResumePoint p = db.resume_run(run);
  EXPECT_EQ(p.first_incomplete_step, 2);
  EXPECT_EQ(p.run.status, RunStatus::running);
  EXPECT_EQ(p.gap_from_t_ns, t0 + 7000);  // the last recorded time (step 3's window end)
  EXPECT_GE(p.gap_to_t_ns, p.gap_from_t_ns);
  EXPECT_EQ(p.gap_event.kind, "gap");
  EXPECT_EQ(p.gap_event.step_index, 2);
  EXPECT_THAT(p.gap_event.message, HasSubstr("continuing at step 3"));  // step_index 2, counted from 1
  EXPECT_TRUE(db.is_live(run));

  Reader rd(path);
  EXPECT_EQ(rd.run(run).status, RunStatus::running);
  EXPECT_FALSE(rd.run(run).ended_utc_ns.has_value());
  const auto anchors = rd.anchors(run);
  ASSERT_EQ(anchors.size(), 2u);
  EXPECT_EQ(anchors[1].segment, 1);
  EXPECT_EQ(anchors[1].monotonic_ns, p.gap_to_t_ns);
  const auto events = rd.events(run);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().kind, "gap");
  EXPECT_THAT(events.back().data_json, HasSubstr("\"gap_from_t_ns\":" + std::to_string(t0 + 7000)));

  // Resumed, completed: nothing more to resume.
  db.add_step(completed_step(run, 2, t0 + 8000));
  EXPECT_EQ(db.first_incomplete_step(run), 4);
  db.set_run_status(run, RunStatus::completed);
  EXPECT_THAT([&] { db.resume_run(run); }, ::testing::ThrowsMessage<DatabaseError>(HasSubstr("completed")));
}

TEST(DbLifecycle, AbortedRunCanBeResumedUnknownRunCannot) {
  TestDatabase dir;
  Database db(dir.location());
  const auto run = db.create_run({}).id;
  db.set_run_status(run, RunStatus::aborted);
  EXPECT_FALSE(db.is_live(run));
  const auto p = db.resume_run(run);
  EXPECT_EQ(p.first_incomplete_step, 0);
  EXPECT_THAT(p.gap_event.message, HasSubstr("was aborted"));
  EXPECT_THROW(db.resume_run(run), DatabaseError);  // running now
  EXPECT_THROW(db.resume_run(12345), DatabaseError);
}

}  // namespace

// A sped-up simulated clock stamps samples ahead of the monotonic clock; resuming such a run
// soon after is no reboot, and the gap event must not say the clock restarted. The resumed
// segment's clock starts after the last record, so the run's times stay ordered.
TEST(DbLifecycle, ResumeAfterSamplesStampedAheadDoesNotClaimTheClockRestarted) {
  TestDatabase dir;
  const auto path = dir.location();
  std::int64_t run = 0;
  const std::int64_t ahead = tocd::monotonic_ns() + 30'000'000'000;  // 30 s ahead
  {
    Database db(path);
    NewRun nr;
    nr.clock_factor = 20;
    run = db.create_run(nr).id;
    db.add_step(completed_step(run, 0, ahead));
  }
  Database db(path);
  const ResumePoint p = db.resume_run(run, 20);
  EXPECT_THAT(p.gap_event.message, ::testing::Not(HasSubstr("restarted")));
  EXPECT_THAT(p.gap_event.message, HasSubstr("continuing at step 2"));
  EXPECT_GT(p.gap_to_t_ns, p.gap_from_t_ns);
}

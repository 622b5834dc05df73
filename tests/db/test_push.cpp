// Store-and-forward onto a PostgreSQL server (db push): each run arrives whole and once,
// however often it is pushed, by how many pushes at once, or when the server dies midway; an
// interrupted run arrives marked so and its resumed data follows; the documented roles hold.
// Runs only in the *_pg binary (a server of its own, tests/db/with_pg_server).
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <regex>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_database.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/push.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/writer.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/temp_dir.hpp"

namespace {

using namespace tocd::db;
using ::testing::HasSubstr;
using tocd::db::testing::prediction_of;
using tocd::db::testing::TestDatabase;
using tocd::test::TempDir;

// A finished run with `samples` samples on two channels, steps, events and two predictions of
// its step, the run's own (with its latency) and a later re-prediction (none).
std::int64_t record_run(Database& db, std::int64_t samples, RunStatus end = RunStatus::completed) {
  NewRun nr;
  nr.name = "pushed";
  nr.protocol_text = "name = \"p\"\n";
  const RunRecord run = db.create_run(nr);
  const auto load = db.add_channel({0, run.id, "load", "N", 0, 1000.0});
  const auto power = db.add_channel({0, run.id, "power", "W", 0, 10.0});
  {
    Writer w(db);
    for (std::int64_t i = 0; i < samples; ++i)
      w.enqueue(Sample{i % 10 == 0 ? power.id : load.id, run.monotonic_anchor_ns + 1000 * i, 0.001 * i});
    w.enqueue(EventRecord{0, run.id, run.monotonic_anchor_ns + 5, "step", "step 1", 0, ""});
  }
  StepRecord st;
  st.run_id = run.id;
  st.index = 0;
  st.recorded_from_t_ns = run.monotonic_anchor_ns;
  st.recorded_to_t_ns = run.monotonic_anchor_ns + 1000 * samples;
  st.measured_transmission = 0.5;
  st.channels = {{load.id, 2.0, 0.1, 40}, {power.id, 5e-4, 1e-5, 4}};
  db.add_step(st);
  PredictionRecord timed = prediction_of(run.id, 0, R"({"seed":1})", 0.4);
  timed.total_seconds = 1.5;
  timed.latency_s = 2.25;
  db.add_prediction(timed);
  db.add_prediction(prediction_of(run.id, 0, R"({"seed":2})", 0.41));
  if (end != RunStatus::running) db.set_run_status(run.id, end);
  return run.id;
}

std::int64_t samples_of(const Reader& r, std::int64_t run_id) {
  std::int64_t n = 0;
  for (const auto& ch : r.channels(run_id)) n += r.sample_count(ch.id);
  return n;
}

const RunSummary* by_uuid(const std::vector<RunSummary>& runs, const std::string& uuid) {
  for (const auto& s : runs)
    if (s.run.uuid == uuid) return &s;
  return nullptr;
}

// The server holds each local run once, whole: the same samples, steps, events, predictions.
void expect_server_mirrors(const std::string& file, const std::string& server) {
  const Reader local(file), remote(server);
  const auto there = remote.runs();
  for (const auto& s : local.runs()) {
    if (s.live) continue;
    int copies = 0;
    for (const auto& t : there) copies += t.run.uuid == s.run.uuid;
    ASSERT_EQ(copies, 1) << "run " << s.run.uuid;
    const RunSummary& t = *by_uuid(there, s.run.uuid);
    EXPECT_EQ(samples_of(remote, t.run.id), samples_of(local, s.run.id));
    EXPECT_EQ(t.steps, s.steps);
    EXPECT_EQ(t.events, s.events);
    EXPECT_EQ(t.predictions, s.predictions);
    EXPECT_EQ(t.run.status, shown_status(s));
    EXPECT_EQ(remote.anchors(t.run.id).size(), local.anchors(s.run.id).size());
    const auto pa = local.predictions(s.run.id), pb = remote.predictions(t.run.id);
    ASSERT_EQ(pa.size(), pb.size());
    for (std::size_t i = 0; i < pa.size(); ++i) {
      EXPECT_EQ(pa[i].T, pb[i].T);
      EXPECT_EQ(pa[i].config_json, pb[i].config_json);
      // An unset time stays unset (NaN), a set one arrives exactly.
      for (const auto& [x, y] :
           {std::pair{pa[i].total_seconds, pb[i].total_seconds}, std::pair{pa[i].latency_s, pb[i].latency_s}})
        EXPECT_TRUE(x == y || (std::isnan(x) && std::isnan(y))) << x << " vs " << y;
    }
    const auto a = local.compare(s.run.id), b = remote.compare(t.run.id);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].step.measured_transmission, b[i].step.measured_transmission);
      EXPECT_EQ(a[i].relative_difference, b[i].relative_difference);
    }
  }
}

// The error push_runs(file, target) fails with; a test failure when it succeeds.
std::string push_error(const std::string& file, const std::string& target) {
  try {
    push_runs(file, target);
  } catch (const DatabaseError& e) {
    return e.what();
  }
  ADD_FAILURE() << "the push to '" << target << "' succeeded";
  return "";
}

// A rig's local file and a fresh database on the test server for it to push to.
class PushTest : public ::testing::Test {
 protected:
  // Records a finished run into the local file; its id there.
  std::int64_t record_local(std::int64_t samples, RunStatus end = RunStatus::completed) {
    Database db(file_);
    return record_run(db, samples, end);
  }

  TempDir dir_{"db_push"};
  TestDatabase server_;
  const std::string file_ = (dir_ / "local.db").string();
};
using DbPush = PushTest;
using DbPushFault = PushTest;
using DbRoles = PushTest;
using DbPandasServer = PushTest;

TEST_F(DbPush, EachRunArrivesOnceAndASecondPushAddsNothing) {
  {
    Database db(file_);
    record_run(db, 5000);
    record_run(db, 3000, RunStatus::aborted);
  }
  const auto first = push_runs(file_, server_.location());
  ASSERT_EQ(first.size(), 2u);
  for (const auto& r : first) EXPECT_EQ(r.action, PushAction::copied);
  expect_server_mirrors(file_, server_.location());
  const auto second = push_runs(file_, server_.location());
  for (const auto& r : second) {
    EXPECT_EQ(r.action, PushAction::unchanged);
    EXPECT_EQ(r.server_id, first[static_cast<std::size_t>(&r - second.data())].server_id);
  }
  EXPECT_EQ(Reader(server_.location()).runs().size(), 2u);
  expect_server_mirrors(file_, server_.location());
}

TEST_F(DbPush, AnInterruptedRunArrivesInterruptedAndItsResumeFollows) {
  const std::int64_t run = record_local(2000, RunStatus::running);  // closed while running: a crash
  auto pushed = push_runs(file_, server_.location());
  ASSERT_EQ(pushed.size(), 1u);
  EXPECT_EQ(pushed[0].status, "interrupted");
  const auto server_id = pushed[0].server_id;
  EXPECT_EQ(Reader(server_.location()).run(server_id).status, RunStatus::interrupted);
  {
    Database db(file_);  // marks it interrupted in the file too
    const auto resumed = db.resume_run(run);
    const auto ch = Reader(file_).channel(run, "load")->id;
    {
      Writer w(db);
      for (int i = 0; i < 700; ++i) w.enqueue(Sample{ch, resumed.gap_to_t_ns + 1000 * i, 1.0});
    }
    db.set_run_status(run, RunStatus::completed);
  }
  pushed = push_runs(file_, server_.location());
  ASSERT_EQ(pushed.size(), 1u);
  EXPECT_EQ(pushed[0].action, PushAction::updated);
  EXPECT_EQ(pushed[0].server_id, server_id);  // the same run on the server, now whole
  const Reader remote(server_.location());
  EXPECT_EQ(remote.run(server_id).status, RunStatus::completed);
  EXPECT_EQ(remote.anchors(server_id).size(), 2u);
  EXPECT_EQ(samples_of(remote, server_id), 2700);
  expect_server_mirrors(file_, server_.location());
}

TEST_F(DbPush, ARunStillRecordingIsLeftForALaterPush) {
  Database db(file_);
  const auto run = record_run(db, 100, RunStatus::running);
  auto pushed = push_runs(file_, server_.location());
  ASSERT_EQ(pushed.size(), 1u);
  EXPECT_EQ(pushed[0].action, PushAction::skipped);
  EXPECT_TRUE(Reader(server_.location()).runs().empty());
  db.set_run_status(run, RunStatus::completed);
  pushed = push_runs(file_, server_.location());
  EXPECT_EQ(pushed[0].action, PushAction::copied);
  expect_server_mirrors(file_, server_.location());
}

TEST_F(DbPush, TwoPushesOfTheSameFileAtOnceStoreEachRunOnce) {
  for (int i = 0; i < 3; ++i) record_local(20000);
  std::vector<PushedRun> a, b;
  std::thread t1([&] { a = push_runs(file_, server_.location()); });
  std::thread t2([&] { b = push_runs(file_, server_.location()); });
  t1.join();
  t2.join();
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    // One of the two copied each run; the other found it there.
    EXPECT_EQ((a[i].action == PushAction::copied) + (b[i].action == PushAction::copied), 1);
    EXPECT_EQ(a[i].server_id, b[i].server_id);
  }
  expect_server_mirrors(file_, server_.location());
}

TEST_F(DbPush, BadTargetsAreRefusedNamingWhatIsWrong) {
  record_local(10);
  const auto before = tocd::test::read_file(file_);
  // Nobody listens on port 1.
  EXPECT_THAT(push_error(file_, "postgresql://127.0.0.1:1/lab"),
              HasSubstr("cannot connect to PostgreSQL at 'postgresql://127.0.0.1:1/lab'"));
  const std::string with_password = push_error(file_, "postgresql://tocd:secret@127.0.0.1:1/lab");
  EXPECT_THAT(with_password, HasSubstr("postgresql://tocd:***@127.0.0.1:1/lab"));
  EXPECT_THAT(with_password, ::testing::Not(HasSubstr("secret")));
  EXPECT_THROW(push_runs(file_, "lab.db"), DatabaseError);
  // A URI libpq cannot parse, and a user the server does not know: said, naming the server.
  const std::string bad_port = push_error(file_, "postgresql://localhost:notaport/lab");
  EXPECT_THAT(bad_port, HasSubstr("cannot connect to PostgreSQL at 'postgresql://localhost:notaport/lab'"));
  EXPECT_THAT(bad_port, HasSubstr("port"));
  EXPECT_THAT(push_error(file_, "postgresql://no_such_user@/postgres"),
              HasSubstr("authentication failed for user \"no_such_user\""));
  EXPECT_EQ(tocd::test::read_file(file_), before);  // the file is only read
}

// A server database of schema 3 (made here as this build's without the column that version 4
// adds) is upgraded by the next push: the predictions it held read their latency unset, the
// pushed ones arrive with theirs. A reader only asks for the upgrade.
TEST_F(DbPush, AServerOfSchemaThreeIsUpgradedByThePush) {
  {
    Database server(server_.location());
    NewRun nr;
    nr.protocol_text = "name = \"on the server\"\n";
    const RunRecord run = server.create_run(nr);
    server.add_prediction(prediction_of(run.id, 0, "{}", 0.3));
  }
  server_.exec(
      "ALTER TABLE predictions DROP COLUMN latency_s; UPDATE meta SET value = '3' WHERE key = "
      "'schema_version'");
  try {
    Reader r(server_.location());
    ADD_FAILURE() << "a reader opened a server of schema 3";
  } catch (const DatabaseError& e) {
    EXPECT_THAT(e.what(), HasSubstr("schema version 3"));
  }
  record_local(10);
  ASSERT_EQ(push_runs(file_, server_.location()).size(), 1u);
  const Reader r(server_.location());
  const auto runs = r.runs();
  ASSERT_EQ(runs.size(), 2u);
  const auto old = r.predictions(runs[0].run.id);
  ASSERT_EQ(old.size(), 1u);
  EXPECT_EQ(old[0].T, 0.3);
  EXPECT_TRUE(std::isnan(old[0].latency_s)) << old[0].latency_s;
  expect_server_mirrors(file_, server_.location());
}

TEST_F(DbPush, AServerDatabaseOfAnotherApplicationIsLeftUntouched) {
  record_local(10);
  server_.exec("CREATE TABLE orders(id int)");  // another application's table
  EXPECT_THAT(push_error(file_, server_.location()), HasSubstr("not a tocdlab database"));
}

// The server's cluster, stopped and started as its administrator would (pg_virtualenv's
// temporary cluster "regress").
void server_ctl(const char* action) {
  const char* version = std::getenv("PGVERSION");
  ASSERT_NE(version, nullptr) << "PGVERSION: not inside with_pg_server";
  const std::string cmd = std::string("pg_ctlcluster ") + version + " regress " + action + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

TEST_F(DbPushFault, ServerKilledMidPushLeavesNoHalfRunAndTheNextPushCompletesIt) {
  for (int i = 0; i < 4; ++i) record_local(300000);
  std::atomic<bool> done{false};
  std::string error;
  std::thread pusher([&] {
    try {
      push_runs(file_, server_.location());
    } catch (const DatabaseError& e) {
      error = e.what();
    }
    done = true;
  });
  // Kill the server (immediate shutdown: no clean close for the push's session) once the
  // first run is there, while the next one is being copied.
  for (int i = 0; i < 600 && !done; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    try {
      if (!Reader(server_.location()).runs().empty()) break;
    } catch (const DatabaseError&) {  // schema not there yet
    }
  }
  server_ctl("stop -m immediate");
  pusher.join();
  ASSERT_FALSE(error.empty()) << "the push finished before the server was stopped";
  EXPECT_THAT(error, HasSubstr("was not pushed, nothing of it is on the server"));
  server_ctl("start");
  // What the server kept: whole runs only.
  {
    const Reader local(file_), remote(server_.location());
    const auto there = remote.runs(), here = local.runs();
    EXPECT_LT(there.size(), 4u);
    for (const auto& t : there) {
      const auto* s = by_uuid(here, t.run.uuid);
      ASSERT_NE(s, nullptr);
      EXPECT_EQ(samples_of(remote, t.run.id), samples_of(local, s->run.id));
    }
  }
  const auto again = push_runs(file_, server_.location());
  int copied = 0;
  for (const auto& r : again) copied += r.action == PushAction::copied;
  EXPECT_GE(copied, 1);
  expect_server_mirrors(file_, server_.location());
}

TEST_F(DbPushFault, ARigRecordsLocallyWhileTheServerIsDownAndPushesLater) {
  server_ctl("stop -m fast");
  record_local(1000);
  EXPECT_THROW(push_runs(file_, server_.location()), DatabaseError);
  server_ctl("start");
  const auto pushed = push_runs(file_, server_.location());
  ASSERT_EQ(pushed.size(), 1u);
  EXPECT_EQ(pushed[0].action, PushAction::copied);
  expect_server_mirrors(file_, server_.location());
}

// docs/database.md's roles block, as written.
std::string roles_sql() {
  std::smatch m;
  const std::string text = tocd::test::read_file(TOCD_DATABASE_MD);
  if (!std::regex_search(text, m, std::regex("<!-- roles-sql -->\\s*```sql\\n([\\s\\S]*?)```"))) return "";
  return m[1];
}

TEST_F(DbRoles, TheRigWritesTheAnalystOnlyReads) {
  record_local(1000);
  push_runs(file_, server_.location());  // the owner creates the schema
  const std::string sql = roles_sql();
  ASSERT_FALSE(sql.empty()) << "no ```sql block after <!-- roles-sql --> in " << TOCD_DATABASE_MD;
  const std::string& name = server_.name();
  const std::string pw = std::getenv("PGPASSWORD");
  TestDatabase::admin("DROP ROLE IF EXISTS tocd_rig; DROP ROLE IF EXISTS tocd_analyst");
  server_.exec(sql + "; ALTER ROLE tocd_rig PASSWORD '" + pw + "'; ALTER ROLE tocd_analyst PASSWORD '" + pw +
               "'");
  const std::string rig = "postgresql://tocd_rig@/" + name, analyst = "postgresql://tocd_analyst@/" + name;
  // The rig records into the server directly and pushes.
  {
    Database db(rig);
    record_run(db, 500);
  }
  record_local(700);
  push_runs(file_, rig);
  // The analyst reads everything...
  const Reader reader(analyst);
  const auto runs = reader.runs();
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(samples_of(reader, runs[0].run.id), 1000);
  // ...and can change nothing.
  try {
    Database db(analyst);
    db.set_run_status(runs[0].run.id, RunStatus::aborted);
    FAIL() << "the analyst changed a run";
  } catch (const DatabaseError& e) {
    EXPECT_THAT(e.what(), HasSubstr("permission denied"));
  }
  record_local(10);
  EXPECT_THROW(push_runs(file_, analyst), DatabaseError);
  EXPECT_EQ(Reader(server_.location()).runs().size(), 3u);
  EXPECT_EQ(Reader(server_.location()).run(runs[0].run.id).status, RunStatus::completed);
}

}  // namespace

namespace {

TEST_F(DbPandasServer, TheDocumentedReadSqlExampleReadsThePushedRun) {
  record_local(4000);
  const auto pushed = push_runs(file_, server_.location());
  const std::string cmd = std::string(TOCD_SYSTEM_PYTHON) + " " + TOCD_PANDAS_SERVER_CHECK + " " +
                          TOCD_DATABASE_MD + " '" + server_.location() + "' " +
                          std::to_string(pushed[0].server_id) + " 4000 1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

}  // namespace

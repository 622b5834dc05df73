// Steps are true or not recorded: a refused or failed move, a pin short of its target, a
// recording window with a fault or too few readings never becomes a completed step; the
// tester's own limits are written; storage faults end the run; a second abort stops at once.
#include <chrono>
#include <filesystem>
#include <regex>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include "engine_fixture.hpp"
#include "fake_rig.hpp"
#include "protocol_text.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/test/sqlite_pages.hpp"

using namespace tocd::acquisition;
using namespace tocd::acquisition::testing;
namespace fs = std::filesystem;

namespace {

class StepTruth : public EngineFixture {
 protected:
  /// Events reach the file through the writer (a commit every 0.1 s): wait for one.
  bool event_lands(std::int64_t run, const std::string& kind, const std::string& text) const {
    return eventually([&] { return has_event(tocd::db::Reader(path_), run, kind, text); }, 5.0);
  }

  /// The number of instrument faults that an event of `kind` starting `text` names ("... N
  /// instrument fault(s)"), or -1 when no such event is in the run's file.
  static int faults_named(const tocd::db::Reader& r, std::int64_t run, const std::string& kind,
                          const std::string& text) {
    static const std::regex count(R"((\d+) instrument fault\(s\))");
    for (const auto& e : r.events(run)) {
      std::smatch m;
      if (e.kind == kind && e.message.rfind(text, 0) == 0 && std::regex_search(e.message, m, count))
        return std::stoi(m[1].str());
    }
    return -1;
  }

  static std::string events_text(const tocd::db::Reader& r, std::int64_t run) {
    std::string out;
    for (const auto& e : r.events(run)) out += e.kind + ": " + e.message + "\n";
    return out;
  }

  /// Every completed step's mean displacement is within the protocol's tolerance of its target.
  static void expect_steps_at_target(const tocd::db::Reader& r, std::int64_t run, const Protocol& p) {
    const auto d = r.channel(run, "displacement");
    ASSERT_TRUE(d);
    for (const auto& s : r.steps(run)) {
      EXPECT_TRUE(s.completed);
      const auto* st = s.stats_for(d->id);
      ASSERT_NE(st, nullptr);
      EXPECT_NEAR(st->mean, p.steps[s.index].displacement_mm, p.position_tolerance_mm) << "step " << s.index;
    }
  }

  /// The run's file holds `count` steps, every one completed at its target.
  void expect_recorded_at_target(std::int64_t run, const Protocol& p, std::size_t count) const {
    const tocd::db::Reader r(path_);
    ASSERT_EQ(r.steps(run).size(), count);
    expect_steps_at_target(r, run, p);
  }
};

using tocd::test::page_count;

std::string with(std::string text, const std::string& after, const std::string& line) {
  const auto at = text.find(after);
  EXPECT_NE(at, std::string::npos) << after;
  text.insert(at + after.size(), "\n" + line);
  return text;
}

}  // namespace

TEST_F(StepTruth, RefusedMovePausesNamingTheCommandAndTheAnswerThenResumeRecordsAtTarget) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  world->refuse_moves = 1;
  tocd::db::Database db(path_);
  const Protocol p = parse_protocol(pin_protocol("0.25, 0.5"), "truth.toml");
  Engine engine(db, make_fake_instruments(world), fast());
  const auto run = engine.start(p);
  ASSERT_TRUE(eventually([&] { return engine.state() == EngineState::paused; }));
  {
    EXPECT_TRUE(
        event_lands(run, "fault",
                    "command 'move to 1.2500 mm at 0.5 mm/s' failed: fake tester: target, velocity, move "
                    "command: refused with Modbus exception 3"));
    EXPECT_TRUE(
        event_lands(run, "state", "paused: step 1: the mechanical tester did not carry out 'move to"));
    const tocd::db::Reader r(path_);
    EXPECT_TRUE(r.steps(run).empty());  // nothing recorded at the old pin position
  }
  EXPECT_NEAR(world->position_mm(), 0.0, 1e-9);  // the pin never left home
  engine.resume();
  EXPECT_EQ(engine.wait(), EngineState::completed) << engine.error();
  expect_recorded_at_target(run, p, 2u);
}

TEST_F(StepTruth, RefusedMoveInterruptsWhenTheProtocolSaysSo) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  world->refuse_moves = 1;
  tocd::db::Database db(path_);
  const auto text =
      with(pin_protocol("0.25, 0.5"), "retract_speed_mm_per_s = 2", "on_move_failure = \"interrupt\"");
  Engine engine(db, make_fake_instruments(world), fast());
  const auto run = engine.start(parse_protocol(text, "truth.toml"));
  EXPECT_EQ(engine.wait(), EngineState::interrupted);
  EXPECT_NE(engine.error().find("did not carry out 'move to 1.2500 mm at 0.5 mm/s'"), std::string::npos)
      << engine.error();
  const tocd::db::Reader r(path_);
  EXPECT_EQ(r.run(run).status, tocd::db::RunStatus::interrupted);
  EXPECT_TRUE(r.steps(run).empty());
  EXPECT_EQ(r.first_incomplete_step(run), 0);
}

TEST_F(StepTruth, AnUnattendedRunEndsInterruptedWhereItWouldPauseForAFault) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  EngineOptions o = fast();
  o.unattended = true;
  Engine engine(db, make_fake_instruments(world), o);
  const auto run = engine.start(parse_protocol(pin_protocol("0.25, 0.5"), "truth.toml"));
  ASSERT_TRUE(eventually([&] { return engine.state() == EngineState::settling; }));
  world->refuse_moves = 1;  // the second step's move
  EXPECT_EQ(engine.wait(), EngineState::interrupted);
  EXPECT_NE(engine.error().find("step 2: the mechanical tester did not carry out"), std::string::npos)
      << engine.error();
  EXPECT_NE(engine.error().find("resume the run to redo them"), std::string::npos) << engine.error();
  const tocd::db::Reader r(path_);
  EXPECT_EQ(r.steps(run).size(), 1u);
  EXPECT_EQ(r.first_incomplete_step(run), 1);
}

TEST_F(StepTruth, APinThatStopsShortOfItsTargetHasNotArrived) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  world->move_short_by_mm = 0.05;  // five times the 0.01 mm tolerance; the tester says "at target"
  tocd::db::Database db(path_);
  EngineOptions o = fast();
  o.move_timeout_margin_s = 1.0;
  Engine engine(db, make_fake_instruments(world), o);
  const auto run = engine.start(parse_protocol(pin_protocol("0.25"), "truth.toml"));
  ASSERT_TRUE(eventually([&] { return engine.state() == EngineState::paused; }));
  engine.abort("test");
  EXPECT_EQ(engine.wait(), EngineState::aborted);
  const tocd::db::Reader r(path_);
  EXPECT_TRUE(
      has_event(r, run, "state", "did not reach 1.2500 mm within 0.01 mm in time: at 1.2000 mm, stopped"))
      << events_text(r, run);
  EXPECT_TRUE(r.steps(run).empty());
}

TEST_F(StepTruth, APredictionUsesTheDisplacementMeasuredInTheWindow) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  world->move_short_by_mm = 0.004;  // within the 0.01 mm tolerance: recorded, at 0.246 mm
  auto predictor = std::make_shared<FakePredictor>();
  tocd::db::Database db(path_);
  Engine engine(db, make_fake_instruments(world), fast(), predictor);
  const auto run = engine.start(parse_protocol(pin_protocol("0.25"), "truth.toml"));
  EXPECT_EQ(engine.wait(), EngineState::completed) << engine.error();
  const tocd::db::Reader r(path_);
  const auto preds = r.predictions(run);
  ASSERT_EQ(preds.size(), 1u);
  const auto config = nlohmann::json::parse(preds[0].config_json);
  EXPECT_NEAR(config["displacement_mm"].get<double>(), 0.246, 1e-6);
  EXPECT_DOUBLE_EQ(r.steps(run).at(0).target_displacement_mm, 0.25);
}

TEST_F(StepTruth, AWindowWithAFaultIsRecordedAgain) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  const Protocol p = parse_protocol(pin_protocol("0.25, 0.5"), "truth.toml");
  Engine engine(db, make_fake_instruments(world), fast());
  const auto run = engine.start(p);
  ASSERT_TRUE(eventually([&] { return engine.state() == EngineState::recording; }));
  world->nan_power_readings = 2;  // inside step 1's recording window
  EXPECT_EQ(engine.wait(), EngineState::completed) << engine.error();
  const tocd::db::Reader r(path_);
  EXPECT_TRUE(has_event(r, run, "fault", "power meter: reading nan W is not a number"))
      << events_text(r, run);
  // Both bad readings land in the window unless a loaded machine let it close between them
  // (the second then spoils the window recorded again, which is recorded once more).
  const int seen = faults_named(r, run, "step", "step 1: recording window is not a measurement (");
  EXPECT_GE(seen, 1) << events_text(r, run);
  EXPECT_LE(seen, 2) << events_text(r, run);
  EXPECT_TRUE(has_event(r, run, "step", "recording it again (1 of 2)"));
  ASSERT_EQ(r.steps(run).size(), 2u);
  expect_steps_at_target(r, run, p);
  // The recorded window is the clean one: every power reading in it is a number.
  EXPECT_TRUE(std::isfinite(r.steps(run)[0].measured_transmission));
}

TEST_F(StepTruth, AWindowThatStaysFaultyLeavesTheStepWithoutARowAndPausesResumeRedoesIt) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  const auto text = with(pin_protocol("0.25, 0.5"), "record_s = 1", "max_rerecords = 0");
  const Protocol p = parse_protocol(text, "truth.toml");
  std::int64_t run = 0;
  {
    Engine engine(db, make_fake_instruments(world), fast());
    run = engine.start(p);
    ASSERT_TRUE(eventually([&] { return engine.state() == EngineState::recording; }));
    world->fail_tester_reads = 3;
    ASSERT_TRUE(eventually([&] { return engine.state() == EngineState::paused; }));
    {
      EXPECT_TRUE(event_lands(run, "state", "paused: step 1 not recorded after 1 recording(s): "));
      // The three failed reads come one per poll from wherever the window was when the test
      // saw it recording; on a loaded machine the window can close before the last of them.
      // So the pause names the faults its window saw: at least one, at most the three made.
      const int seen = faults_named(tocd::db::Reader(path_), run, "state",
                                    "paused: step 1 not recorded after 1 recording(s): ");
      EXPECT_GE(seen, 1);
      EXPECT_LE(seen, 3);
      const tocd::db::Reader r(path_);
      EXPECT_TRUE(r.steps(run).empty());
    }
    engine.abort("test");
    EXPECT_EQ(engine.wait(), EngineState::aborted);
  }
  {
    const tocd::db::Reader r(path_);
    EXPECT_EQ(r.first_incomplete_step(run), 0);  // resume starts at the step left incomplete
  }
  Engine again(db, make_fake_instruments(world), fast());
  again.resume(run);
  EXPECT_EQ(again.wait(), EngineState::completed) << again.error();
  expect_recorded_at_target(run, p, 2u);
}

TEST_F(StepTruth, TooFewReadingsInTheWindowIsNotAMeasurement) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  // A tester read takes 1 ms of real time: at most 1000 readings per real second, a quarter of
  // the 200 Hz x 20 the protocol asks for, under the default 80 %.
  world->tester_read_delay_us = 1000;
  tocd::db::Database db(path_);
  const auto text = with(pin_protocol("0.25"), "record_s = 1", "max_rerecords = 0");
  Engine engine(db, make_fake_instruments(world), fast());
  const auto run = engine.start(parse_protocol(text, "truth.toml"));
  ASSERT_TRUE(eventually([&] { return engine.state() == EngineState::paused; }));
  engine.abort("test");
  engine.wait();
  const tocd::db::Reader r(path_);
  EXPECT_TRUE(has_event(r, run, "state", "displacement readings of 200 expected (at least 80 % needed)"))
      << events_text(r, run);
  EXPECT_TRUE(r.steps(run).empty());
}

TEST_F(StepTruth, TheProtocolsLimitsAreWrittenToTheTesterAtStartAndOnResume) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  std::int64_t run = 0;
  {
    Engine engine(db, make_fake_instruments(world), fast());
    run = engine.start(parse_protocol(pin_protocol("0.25, 0.5", 7.5), "truth.toml"));
    EXPECT_EQ(world->set_limits_calls, 1);
    EXPECT_DOUBLE_EQ(world->limit_travel_mm, 3.0);  // contact 1 mm + thickness 2 mm: the glass
    EXPECT_DOUBLE_EQ(world->limit_load_N, 7.5);
    engine.abort("test");
    engine.wait();
  }
  world->limit_load_N = 0.0;
  Engine again(db, make_fake_instruments(world), fast());
  again.resume(run);
  EXPECT_EQ(world->set_limits_calls, 2);
  EXPECT_DOUBLE_EQ(world->limit_load_N, 7.5);
  EXPECT_EQ(again.wait(), EngineState::completed) << again.error();
}

TEST_F(StepTruth, AFullDatabaseEndsTheRunInterruptedAndKeepsWhatWasCommitted) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  EngineOptions o = fast();
  // The writer may not grow the file beyond a few pages more than it has now: the samples
  // of the first step fill them (PRAGMA max_page_count, as a full disk would).
  o.writer.max_page_count = page_count(path_) + 40;
  Engine engine(db, make_fake_instruments(world), o);
  const auto run =
      engine.start(parse_protocol(pin_protocol("0.25, 0.5, 0.75", 50.0, 5.0, 1000.0), "truth.toml"));
  EXPECT_EQ(engine.wait(), EngineState::interrupted);
  EXPECT_NE(engine.error().find("storage: a database commit failed"), std::string::npos) << engine.error();
  EXPECT_NE(engine.error().find("full"), std::string::npos) << engine.error();
  const auto st = engine.stats();
  EXPECT_GT(st.writer.failed_samples, 0u);
  const tocd::db::Reader r(path_);
  EXPECT_EQ(r.run(run).status, tocd::db::RunStatus::interrupted);
  EXPECT_LT(r.steps(run).size(), 3u);
  std::int64_t stored = 0;
  for (const auto& c : r.channels(run)) stored += r.sample_count(c.id);
  EXPECT_GT(stored, 0);  // what was committed before the file was full stays
  EXPECT_LE(static_cast<std::uint64_t>(stored), st.writer.written);
}

TEST_F(StepTruth, StopNowStopsThePinWhereItIsWithoutRetracting) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  Engine engine(db, make_fake_instruments(world), fast());
  const auto run = engine.start(parse_protocol(pin_protocol("0.25, 0.5"), "truth.toml"));
  ASSERT_TRUE(eventually([&] { return engine.state() == EngineState::holding; }));
  const auto t0 = std::chrono::steady_clock::now();
  engine.stop_now("second Ctrl-C");
  EXPECT_EQ(engine.wait(), EngineState::aborted);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(2));
  EXPECT_NEAR(world->position_mm(), 1.25, 0.01);  // not retracted
  const tocd::db::Reader r(path_);
  EXPECT_TRUE(has_event(r, run, "operator", "stopped at once: the pin is left at 1.25"))
      << events_text(r, run);
}

TEST_F(StepTruth, PollersAtTheSlowestRatesWakeAtOnceWhenTheRunStops) {
  // Real time, 1 Hz power and 10 Hz tester polling: a poller sleeping out its whole period
  // would hold the end of the run up to 1 s.
  auto world = std::make_shared<FakeWorld>(1.0);
  tocd::db::Database db(path_);
  auto text = pin_protocol("0.25", 50.0, 2.0, 10.0);
  text.replace(text.find("power_Hz = 10"), 13, "power_Hz = 1");
  EngineOptions o;
  o.clock_factor = 1.0;
  Engine engine(db, make_fake_instruments(world), o);
  engine.start(parse_protocol(text, "truth.toml"));
  ASSERT_TRUE(eventually([&] { return engine.state() == EngineState::moving; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(150));  // both pollers asleep by now
  const auto t0 = std::chrono::steady_clock::now();
  engine.stop_now("test");
  EXPECT_EQ(engine.wait(), EngineState::aborted);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(s, 0.3) << "the run took " << s << " s to end";
}

TEST_F(StepTruth, AnObserverThatThrowsNeverTakesAnEngineThreadDown) {
  struct Throwing : EngineObserver {
    void on_samples(std::span<const LiveSample>) override { throw std::runtime_error("samples"); }
    void on_step_recorded(const StepResult&) override { throw std::runtime_error("step"); }
    void on_prediction(int, const PredictedStep&) override { throw std::runtime_error("prediction"); }
    void on_event(const tocd::db::EventRecord&) override { throw std::runtime_error("event"); }
    void on_state(EngineState, const std::string&) override { throw std::runtime_error("state"); }
    void on_progress(const Progress&) override { throw std::runtime_error("progress"); }
  } observer;
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  Engine engine(db, make_fake_instruments(world), fast(), std::make_shared<FakePredictor>(), &observer);
  const auto run = engine.start(parse_protocol(pin_protocol("0.25, 0.5"), "truth.toml"));
  EXPECT_EQ(engine.wait(), EngineState::completed) << engine.error();
  const tocd::db::Reader r(path_);
  EXPECT_EQ(r.steps(run).size(), 2u);
  EXPECT_EQ(r.predictions(run).size(), 2u);
}

#include <array>
#include <chrono>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>
#include <tuple>

#include <gtest/gtest.h>

#include "engine_fixture.hpp"
#include "fake_rig.hpp"
#include "forwarding_tester.hpp"
#include "protocol_text.hpp"
#include "tocd/acquisition/compare_table.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/test/eventually.hpp"

using namespace tocd::acquisition;
using namespace tocd::acquisition::testing;
namespace fs = std::filesystem;

// Named, not anonymous: gtest derives each TEST_F class (external linkage) from the fixture.
namespace engine_test_support {

class EngineTest : public EngineFixture {
 protected:
  struct BusySimulatorRun;
  struct ObservedRun;
};

/// Records observer callbacks (called from engine threads).
struct Recorder : EngineObserver {
  std::mutex mu;
  std::vector<EngineState> states;
  std::vector<StepResult> steps;
  std::atomic<int> live{0}, predictions{0}, progress{0};
  std::map<int, double> latency_s;  ///< by step, as the predictions landed
  void on_samples(std::span<const LiveSample> s) override { live += static_cast<int>(s.size()); }
  void on_step_recorded(const StepResult& r) override {
    std::lock_guard lock(mu);
    steps.push_back(r);
  }
  void on_prediction(int step, const PredictedStep& p) override {
    std::lock_guard lock(mu);
    latency_s[step] = p.latency_s;
    ++predictions;
  }
  void on_state(EngineState s, const std::string&) override {
    std::lock_guard lock(mu);
    states.push_back(s);
  }
  void on_progress(const Progress&) override { ++progress; }
  int step_count() {
    std::lock_guard lock(mu);
    return static_cast<int>(steps.size());
  }
};

/// A run of the pin protocol's `steps` on the fake rig, the engine's callbacks recorded.
struct EngineTest::ObservedRun {
  ObservedRun(const fs::path& db_path, const std::string& steps)
      : db(db_path),
        engine(db, make_fake_instruments(world), EngineFixture::fast(), nullptr, &obs),
        run(engine.start(parse_protocol(pin_protocol(steps), "engine.toml"))) {}
  /// What a test drives and checks: the fake rig's world, the observer, the engine and the run's id.
  auto parts() { return std::tie(world, obs, engine, run); }

  std::shared_ptr<FakeWorld> world = std::make_shared<FakeWorld>(EngineFixture::kFactor);
  Recorder obs;
  tocd::db::Database db;
  Engine engine;
  std::int64_t run = 0;
};

/// A three-step run whose simulator is busy (its gate closed) until the test opens it.
struct EngineTest::BusySimulatorRun {
  explicit BusySimulatorRun(const fs::path& db_path)
      : db(db_path), engine(db, make_fake_instruments(world), EngineFixture::fast(), predictor, &obs) {
    predictor->close_gate();
    run = engine.start(parse_protocol(pin_protocol("0.25, 0.5, 0.75"), "engine.toml"));
  }
  /// Whether the recording ends (every step recorded) within the fixture's wait.
  bool recording_completed() {
    return tocd::test::eventually([&] {
      std::lock_guard lock(obs.mu);
      return !obs.states.empty() && obs.states.back() == EngineState::completed;
    });
  }
  /// What a test drives and checks: the simulator's gate, the engine and the run's id.
  auto parts() { return std::tie(predictor, engine, run); }

  std::shared_ptr<FakeWorld> world = std::make_shared<FakeWorld>(EngineFixture::kFactor);
  std::shared_ptr<FakePredictor> predictor = std::make_shared<FakePredictor>();
  Recorder obs;
  tocd::db::Database db;
  Engine engine;
  std::int64_t run = 0;
};

}  // namespace engine_test_support

using namespace engine_test_support;

TEST_F(EngineTest, RecordsStepsWithTransmissionLoadAndPredictions) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  // A short fault streak: the tare's read fails (the run goes on untared), then 3 poller reads
  // (logged, retried, recovered).
  world->fail_tester_reads = 4;
  auto predictor = std::make_shared<FakePredictor>(1.02);
  predictor->work = std::chrono::milliseconds(30);
  Recorder obs;
  tocd::db::Database db(path_);
  const Protocol p = parse_protocol(pin_protocol("0.25, 0.5, 0.75"), "engine.toml");
  Engine engine(db, make_fake_instruments(world), fast(), predictor, &obs);
  const auto began = std::chrono::steady_clock::now();
  const auto run = engine.start(p);
  EXPECT_EQ(engine.wait(), EngineState::completed) << engine.error();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();

  const tocd::db::Reader r(path_);
  EXPECT_EQ(r.run(run).status, tocd::db::RunStatus::completed);
  // The fault streak began with the load-cell tare's read: the run went on untared.
  EXPECT_TRUE(has_event(r, run, "tare", "not tared (recorded loads include the cell's offset): fake tester"));
  const auto steps = r.steps(run);
  ASSERT_EQ(steps.size(), 3u);
  const auto load_ch = r.channel(run, "load");
  const auto power_ch = r.channel(run, "power");
  ASSERT_TRUE(load_ch && power_ch);
  for (const auto& s : steps) {
    const double d = p.steps[s.index].displacement_mm;
    EXPECT_TRUE(s.completed);
    EXPECT_DOUBLE_EQ(s.target_displacement_mm, d);
    EXPECT_DOUBLE_EQ(s.nominal_strain, d / 2.0);
    // Power noise is 0.01 % per reading, so even one reading gives T within 1e-4 absolute.
    EXPECT_NEAR(s.measured_transmission, world->transmission(d, FakeWorld::kAtmosphere_kPa), 1e-4);
    const auto* load = s.stats_for(load_ch->id);
    ASSERT_NE(load, nullptr);
    // Settled: the relaxation overshoot (20 %, tau 0.3 s) has decayed below the 0.05 N/s rate
    // criterion, i.e. to < 0.05 * 0.3 / load of the load; 2 % covers it at these loads.
    EXPECT_NEAR(load->mean, world->equilibrium_load_N(d), 0.02 * world->equilibrium_load_N(d) + 0.016);
    // 1 s at 10 Hz: 10 readings, fewer when a loaded machine delays the poller of this 20x
    // fast clock past the window (its late readings are stamped when taken), and more when it
    // catches up inside the window (late polls run back to back). Whatever the machine's load,
    // the window counts no reading that was not stored: at most those stamped from one period
    // before its start (a reading taken just before the window opened and handed over after)
    // to its end.
    const auto power_n = s.stats_for(power_ch->id)->n;
    EXPECT_GE(power_n, 5);
    tocd::db::SampleQuery window;
    window.from_t_ns = s.recorded_from_t_ns - 100'000'000;  // one 10 Hz period of simulated time
    window.to_t_ns = s.recorded_to_t_ns;
    EXPECT_LE(static_cast<std::size_t>(power_n), r.samples(power_ch->id, window).size());
    EXPECT_LT(s.settled_t_ns, s.recorded_from_t_ns);
    EXPECT_LT(s.recorded_from_t_ns, s.recorded_to_t_ns);
  }
  // Predictions land next to their steps.
  const auto rows = r.compare(run);
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) {
    ASSERT_TRUE(row.prediction);
    EXPECT_NEAR(row.prediction->T, 1.02 * row.step.measured_transmission, 1e-12);
    EXPECT_NEAR(row.relative_difference, 0.02, 1e-9);
    // Its latency, real time from the queue receiving the step to the prediction being stored,
    // lies within the run and covers the predictor's own work; the observer heard the same.
    const double latency = row.prediction->latency_s;
    EXPECT_GE(latency, row.prediction->total_seconds) << "step " << row.step.index;
    EXPECT_GE(row.prediction->total_seconds, 0.03);
    EXPECT_LE(latency, wall_s) << "step " << row.step.index;
    std::lock_guard lock(obs.mu);
    EXPECT_EQ(obs.latency_s[row.step.index], latency) << "step " << row.step.index;
  }
  // The compare table shows each step with its prediction and the relative difference.
  const CompareTable table = compare_table(r, run);
  ASSERT_EQ(table.lines.size(), 3u);
  EXPECT_DOUBLE_EQ(table.lines[1].displacement_mm, 0.5);
  EXPECT_NEAR(table.lines[1].load_N, world->equilibrium_load_N(0.5), 0.05);
  const std::string text = format_compare_table(table);
  EXPECT_NE(text.find(fmt::format("{:.5f} +- 0.00100", table.lines[2].predicted_T)), std::string::npos)
      << text;
  EXPECT_NE(text.find("+2.00 %"), std::string::npos) << text;
  EXPECT_EQ(to_json(table)["steps"][2]["predicted_T"].get<double>(), table.lines[2].predicted_T);
  EXPECT_EQ(obs.predictions, 3);
  EXPECT_EQ(obs.step_count(), 3);
  EXPECT_GT(obs.live, 100);
  EXPECT_GT(obs.progress, 0);
  EXPECT_TRUE(has_event(r, run, "fault", "mechanical tester"));
  EXPECT_TRUE(has_event(r, run, "retry", "recovered after 3 failed reads"));
  EXPECT_NEAR(world->position_mm(), 0.0, 1e-9);  // retracted home at the end
  // Every sample the engine enqueued is in the file.
  std::int64_t stored = 0;
  for (const auto& c : r.channels(run)) stored += r.sample_count(c.id);
  EXPECT_EQ(static_cast<std::uint64_t>(stored), engine.stats().samples_enqueued);
  EXPECT_EQ(engine.stats().samples_dropped, 0u);
}

TEST_F(EngineTest, LoadCellIsTaredClearOfTheSampleBeforeAPinRun) {
  // The cell reads 0.05 N unloaded. Tared at home (0 mm; contact at 1 mm), the recorded loads
  // are the sample's alone: 0 at contact, where the offset would exceed the tolerance 3x.
  auto world = std::make_shared<FakeWorld>(kFactor);
  world->load_cell_offset_N = 0.05;
  tocd::db::Database db(path_);
  const Protocol p = parse_protocol(pin_protocol("0.0, 0.5"), "engine.toml");
  Engine engine(db, make_fake_instruments(world), fast());
  const auto run = engine.start(p);
  EXPECT_EQ(engine.wait(), EngineState::completed) << engine.error();
  EXPECT_EQ(world->tare_calls, 1);
  const tocd::db::Reader r(path_);
  EXPECT_TRUE(has_event(r, run, "tare", "load cell tared at 0.000 mm"));
  const auto load_ch = r.channel(run, "load");
  ASSERT_TRUE(load_ch);
  const auto steps = r.steps(run);
  ASSERT_EQ(steps.size(), 2u);
  for (const auto& s : steps) {
    const double eq = world->equilibrium_load_N(p.steps[s.index].displacement_mm);
    EXPECT_NEAR(s.stats_for(load_ch->id)->mean, eq, 0.02 * eq + 0.016) << "step " << s.index;
  }
}

TEST_F(EngineTest, LoadCellIsNotTaredUnderLoadOrWhenTheProtocolSaysSo) {
  for (const bool pin_in_sample : {true, false}) {
    SCOPED_TRACE(pin_in_sample ? "pin in the sample" : "tare_load = false");
    auto world = std::make_shared<FakeWorld>(kFactor);
    world->load_cell_offset_N = 0.05;
    if (pin_in_sample) {
      std::lock_guard lock(world->mu);
      world->pos0_mm = world->target_mm = 1.2;  // 0.2 mm past contact: taring would hide load
    }
    const fs::path db_path = dir_ / (pin_in_sample ? "in_sample.db" : "no_tare.db");
    tocd::db::Database db(db_path);
    Protocol p = parse_protocol(pin_protocol("0.5"), "engine.toml");
    p.tare_load = pin_in_sample;  // in the sample the engine must decline on its own
    Engine engine(db, make_fake_instruments(world), fast());
    const auto run = engine.start(p);
    EXPECT_EQ(engine.wait(), EngineState::completed) << engine.error();
    EXPECT_EQ(world->tare_calls, 0);
    const tocd::db::Reader r(db_path);
    EXPECT_EQ(has_event(r, run, "tare", "not tared: the pin is at 1.200 mm"), pin_in_sample);
    const auto load_ch = r.channel(run, "load");
    ASSERT_TRUE(load_ch);
    const double eq = world->equilibrium_load_N(0.5);
    EXPECT_NEAR(r.steps(run).at(0).stats_for(load_ch->id)->mean, eq + 0.05, 0.02 * eq + 0.016);
  }
}

TEST_F(EngineTest, PauseResumeThenAbortRetractsAndKeepsData) {
  ObservedRun observed(path_, "0.25, 0.5, 0.75, 1.0");
  // Lambdas name observed.obs and observed.engine: clang 14 cannot capture structured bindings.
  auto [world, obs, engine, run] = observed.parts();
  ASSERT_TRUE(eventually(
      [&] { return observed.obs.step_count() >= 1 && observed.engine.state() == EngineState::moving; }));
  engine.pause();
  ASSERT_TRUE(eventually([&] { return observed.engine.state() == EngineState::paused; }));
  const int stops = world->stop_calls;
  EXPECT_GE(stops, 1);
  const double held = world->position_mm();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // 2 s simulated
  EXPECT_NEAR(world->position_mm(), held, 1e-12);               // the pin stays put while paused
  EXPECT_EQ(obs.step_count(), 1);
  engine.resume();
  ASSERT_TRUE(eventually([&] { return observed.obs.step_count() >= 2; }));
  engine.abort("test abort");
  EXPECT_EQ(engine.wait(), EngineState::aborted);

  const tocd::db::Reader r(path_);
  EXPECT_EQ(r.run(run).status, tocd::db::RunStatus::aborted);
  EXPECT_GE(r.steps(run).size(), 2u);
  EXPECT_LT(r.steps(run).size(), 4u);
  EXPECT_TRUE(has_event(r, run, "state", "paused: operator pause"));
  EXPECT_TRUE(has_event(r, run, "operator", "resumed; redoing step 2"));
  EXPECT_TRUE(has_event(r, run, "operator", "abort: test abort"));
  EXPECT_NEAR(world->position_mm(), 0.0, 1e-9);  // abort retracts the pin
  EXPECT_GT(r.sample_count(r.channel(run, "load")->id), 100);
  EXPECT_EQ(engine.stats().samples_dropped, 0u);
}

TEST_F(EngineTest, LoadLimitTripStopsMotionRecordsWhyAndLeavesResumableRun) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  // Step 3 (1.5 mm) needs 4 * 1.5^1.5 = 7.3 N: the 5 N limit trips on the way down, where
  // the moving load 1.2 * 4 d^1.5 reaches it, at d = (5/4.8)^(2/3) = 1.03 mm.
  Engine engine(db, make_fake_instruments(world), fast());
  const auto run = engine.start(parse_protocol(pin_protocol("0.25, 0.5, 1.5", 5.0), "engine.toml"));
  EXPECT_EQ(engine.wait(), EngineState::interrupted);
  EXPECT_NE(engine.error().find("above the 5.000 N limit"), std::string::npos) << engine.error();
  EXPECT_GE(world->stop_calls, 1);

  const tocd::db::Reader r(path_);
  EXPECT_EQ(r.run(run).status, tocd::db::RunStatus::interrupted);
  EXPECT_TRUE(has_event(r, run, "interlock", "above the 5.000 N limit"));
  EXPECT_EQ(r.first_incomplete_step(run), 2);
  // Motion stopped at the first reading over the limit: from that reading on, the pin went
  // no deeper than the stop command's latency allows (5 um = 10 ms simulated at 0.5 mm/s)
  // and the load never rose further. (How far past 5 N that first reading is depends on the
  // poll spacing, i.e. on scheduling at this fast simulated clock.)
  const auto load = r.samples(r.channel(run, "load")->id);
  const auto disp = r.samples(r.channel(run, "displacement")->id);
  ASSERT_EQ(load.size(), disp.size());
  std::size_t first_over = load.size();
  for (std::size_t i = 0; i < load.size() && first_over == load.size(); ++i)
    if (load[i].value > 5.0) first_over = i;
  ASSERT_LT(first_over, load.size());
  EXPECT_GT(disp[first_over].value, 1.0);  // the trip happened on the way to 1.5 mm
  int deeper = 0, higher = 0;
  for (std::size_t i = first_over; i < load.size(); ++i) {
    deeper += disp[i].value > disp[first_over].value + 0.005;
    higher += load[i].value > load[first_over].value + 0.05;
  }
  EXPECT_EQ(deeper, 0);
  EXPECT_EQ(higher, 0);
  EXPECT_NEAR(world->position_mm(), 0.0, 1e-9);  // then backed off home
}

TEST_F(EngineTest, ResumeContinuesTheSameRunAfterAGap) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  const auto protocol = parse_protocol(pin_protocol("0.25, 0.5, 0.75"), "engine.toml");
  std::int64_t run = 0;
  {
    Recorder obs;
    Engine engine(db, make_fake_instruments(world), fast(), nullptr, &obs);
    run = engine.start(protocol);
    ASSERT_TRUE(eventually([&] { return obs.step_count() >= 1 && engine.state() == EngineState::settling; }));
    world->extra_load_N = 100.0;  // a load spike trips the interlock during step 2
    EXPECT_EQ(engine.wait(), EngineState::interrupted);
  }
  world->extra_load_N = 0.0;
  {
    const tocd::db::Reader r(path_);
    EXPECT_EQ(r.run(run).status, tocd::db::RunStatus::interrupted);
    EXPECT_EQ(r.first_incomplete_step(run), 1);
  }
  auto predictor = std::make_shared<FakePredictor>();
  Engine engine(db, make_fake_instruments(world), fast(), predictor);
  EXPECT_EQ(engine.resume(run), run);
  EXPECT_EQ(engine.wait(), EngineState::completed) << engine.error();

  const tocd::db::Reader r(path_);
  EXPECT_EQ(r.runs().size(), 1u);
  EXPECT_EQ(r.run(run).status, tocd::db::RunStatus::completed);
  const auto steps = r.steps(run);
  ASSERT_EQ(steps.size(), 3u);
  for (const auto& s : steps) EXPECT_TRUE(s.completed);
  EXPECT_EQ(predictor->calls, 2);  // only the steps recorded after the resume
  bool gap = false;
  for (const auto& e : r.events(run)) gap = gap || e.kind == "gap";
  EXPECT_TRUE(gap);
  // Time keeps increasing across the gap: the resumed steps come after the first one.
  EXPECT_GT(steps[1].started_t_ns, steps[0].recorded_to_t_ns);
  EXPECT_GE(r.anchors(run).size(), 2u);
  // A completed run cannot be resumed.
  Engine again(db, make_fake_instruments(world), fast());
  EXPECT_THROW(again.resume(run), EngineError);
}

TEST_F(EngineTest, VacuumSealLossPausesTheRun) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  Recorder obs;
  tocd::db::Database db(path_);
  Engine engine(db, make_fake_instruments(world, false, true), fast(), nullptr, &obs);
  const auto run = engine.start(parse_protocol(vacuum_protocol("80, 60"), "vac.toml"));
  ASSERT_TRUE(eventually([&] { return obs.step_count() >= 1 && engine.state() == EngineState::settling; }));
  world->seal_lost = true;
  ASSERT_TRUE(eventually([&] { return engine.state() == EngineState::paused; }));
  EXPECT_EQ(obs.step_count(), 1);
  world->seal_lost = false;  // the operator reseats the sample
  engine.resume();
  EXPECT_EQ(engine.wait(), EngineState::completed) << engine.error();

  const tocd::db::Reader r(path_);
  EXPECT_TRUE(has_event(r, run, "interlock", "vacuum seal loss"));
  EXPECT_TRUE(has_event(r, run, "state", "paused: vacuum seal loss"));
  const auto steps = r.steps(run);
  ASSERT_EQ(steps.size(), 2u);
  const auto pressure = r.channel(run, "pressure");
  ASSERT_TRUE(pressure);
  EXPECT_NEAR(steps[1].stats_for(pressure->id)->mean, 60.0, 0.5);
  EXPECT_NEAR(steps[1].measured_transmission, world->transmission(0.0, 60.0), 2e-3);
}

TEST_F(EngineTest, PowerOverRangePauses) {
  ObservedRun observed(path_, "0.25, 0.5");
  auto [world, obs, engine, run] = observed.parts();
  ASSERT_TRUE(eventually([&] { return observed.engine.state() == EngineState::settling; }));
  world->power_over_range = true;
  ASSERT_TRUE(eventually([&] { return observed.engine.state() == EngineState::paused; }));
  world->power_over_range = false;
  engine.abort();
  EXPECT_EQ(engine.wait(), EngineState::aborted);
  EXPECT_TRUE(has_event(tocd::db::Reader(path_), run, "interlock", "power meter over range"));
}

TEST_F(EngineTest, PredictionsNeverHoldUpAcquisition) {
  BusySimulatorRun busy(path_);  // the simulator is "busy" for the whole acquisition
  auto [predictor, engine, run] = busy.parts();
  ASSERT_TRUE(busy.recording_completed());
  EXPECT_FALSE(engine.wait_for(std::chrono::milliseconds(50)));  // predictions still pending
  {
    const tocd::db::Reader r(path_);
    EXPECT_EQ(r.steps(run).size(), 3u);
    EXPECT_EQ(r.predictions(run).size(), 0u);
    EXPECT_EQ(r.run(run).status, tocd::db::RunStatus::completed);
  }
  predictor->open_gate();
  EXPECT_EQ(engine.wait(), EngineState::completed);
  const tocd::db::Reader r(path_);
  const auto preds = r.predictions(run);
  ASSERT_EQ(preds.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(preds[i].step_index, i);
}

TEST_F(EngineTest, MeasuredBaselineOfZeroIsRefusedBeforeAnyRun) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  world->source_W = 0.0;
  tocd::db::Database db(path_);
  auto text = pin_protocol("0.25");
  text.replace(text.find("power_W = 1.0e-3"), 16, "measure = true\nmeasure_s = 0.5");
  Engine engine(db, make_fake_instruments(world), fast());
  try {
    engine.start(parse_protocol(text, "engine.toml"));
    FAIL() << "no error";
  } catch (const EngineError& e) {
    EXPECT_NE(std::string(e.what()).find("baseline power is 0 W"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(tocd::db::Reader(path_).runs().empty());
}

TEST_F(EngineTest, MeasuredBaselineIsStoredWithTheRun) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  auto text = pin_protocol("0.25");
  text.replace(text.find("power_W = 1.0e-3"), 16, "measure = true\nmeasure_s = 0.5");
  Engine engine(db, make_fake_instruments(world), fast());
  const auto run = engine.start(parse_protocol(text, "engine.toml"));
  EXPECT_EQ(engine.wait(), EngineState::completed);
  const tocd::db::Reader r(path_);
  // Pin at home: the fake's glass-only power is source x T(0) = 0.2 mW.
  EXPECT_NEAR(r.run(run).baseline_power_W, 1e-3 * world->transmission(0.0, FakeWorld::kAtmosphere_kPa), 1e-7);
  EXPECT_TRUE(has_event(r, run, "baseline", "measured glass-only baseline"));
}

TEST_F(EngineTest, MissingInstrumentIsAClearError) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  Engine pin_without_tester(db, make_fake_instruments(world, false, false), fast());
  EXPECT_THROW(pin_without_tester.start(parse_protocol(pin_protocol("0.25"), "e.toml")), EngineError);
  Engine vacuum_without_pump(db, make_fake_instruments(world, true, false), fast());
  EXPECT_THROW(vacuum_without_pump.start(parse_protocol(vacuum_protocol("80"), "v.toml")), EngineError);
  EXPECT_TRUE(tocd::db::Reader(path_).runs().empty());
}

TEST_F(EngineTest, AnInstrumentThatKeepsFailingInterruptsTheRun) {
  ObservedRun observed(path_, "0.25, 0.5, 0.75");
  auto [world, obs, engine, run] = observed.parts();
  ASSERT_TRUE(eventually([&] { return observed.obs.step_count() >= 1; }));
  world->fail_tester_reads = 1'000'000'000;  // the link is gone for good
  EXPECT_EQ(engine.wait(), EngineState::interrupted);
  EXPECT_NE(engine.error().find("mechanical tester lost: failing for"), std::string::npos) << engine.error();
  const tocd::db::Reader r(path_);
  EXPECT_EQ(r.run(run).status, tocd::db::RunStatus::interrupted);
  EXPECT_TRUE(has_event(r, run, "fault", "mechanical tester: fake tester"));
  EXPECT_TRUE(has_event(r, run, "interlock", "mechanical tester lost"));
  EXPECT_TRUE(has_event(r, run, "fault", "the pin could not be retracted"));
  EXPECT_GE(r.first_incomplete_step(run), 1);
}

// After the last step nothing but the predictions keeps the run: an abort then cancels them
// and the engine ends at once (it waited for every prediction), the run stays completed, and
// each step left unpredicted has an event saying why.
TEST_F(EngineTest, AnAbortAfterTheLastStepCancelsThePredictionsAndEndsAtOnce) {
  BusySimulatorRun busy(path_);  // the simulator is busy until cancelled
  auto [predictor, engine, run] = busy.parts();
  ASSERT_TRUE(busy.recording_completed());
  EXPECT_FALSE(engine.wait_for(std::chrono::milliseconds(50)));
  engine.abort("test abort");
  EXPECT_TRUE(engine.wait_for(std::chrono::seconds(2)));
  EXPECT_EQ(engine.wait(), EngineState::completed);
  const EngineStats s = engine.stats();
  EXPECT_EQ(s.predictions_asked, 3);
  EXPECT_EQ(s.predictions_cancelled, 3);
  EXPECT_EQ(s.predictions_stored, 0);
  const tocd::db::Reader r(path_);
  EXPECT_EQ(r.run(run).status, tocd::db::RunStatus::completed);
  EXPECT_TRUE(has_event(r, run, "prediction", "step 3: not predicted: run aborted: test abort"));
}

// A run whose predictions failed says so: the engine counts them (the command line's exit
// status and summary are built on it).
TEST_F(EngineTest, FailedPredictionsAreCounted) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  auto predictor = std::make_shared<FakePredictor>();
  predictor->fail = true;
  tocd::db::Database db(path_);
  Engine engine(db, make_fake_instruments(world), fast(), predictor);
  const auto run = engine.start(parse_protocol(pin_protocol("0.25, 0.5"), "engine.toml"));
  EXPECT_EQ(engine.wait(), EngineState::completed);
  const EngineStats s = engine.stats();
  EXPECT_EQ(s.predictions_asked, 2);
  EXPECT_EQ(s.predictions_failed, 2);
  EXPECT_EQ(s.predictions_stored, 0);
  EXPECT_TRUE(has_event(tocd::db::Reader(path_), run, "prediction",
                        "step 2: prediction failed: fake simulator failed"));
}

// The run's channel rows are the drivers' capability tables: name and unit as each driver
// describes them, the instrument that reads them, and its poll rate.
TEST_F(EngineTest, ChannelRowsAreWhatTheDriversDescribe) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  const Protocol p = parse_protocol(pin_protocol("0.25"), "engine.toml");
  InstrumentSet set = make_fake_instruments(world, true, true);
  struct Expected {
    std::string name, unit, kind;
    double rate_Hz;
  };
  std::vector<Expected> expected;
  const auto add = [&](const tocd::devices::InstrumentCapabilities& caps, double rate_Hz) {
    for (const auto& c : caps.channels)
      expected.push_back({std::string(c.name), std::string(c.unit), std::string(caps.kind), rate_Hz});
  };
  add(set.tester->describe(), p.rates.tester_Hz);
  add(set.power_meter->describe(), p.rates.power_Hz);
  add(set.vacuum->describe(), p.rates.pressure_Hz);
  Engine engine(db, std::move(set), fast());
  const auto run = engine.start(p);
  ASSERT_EQ(engine.wait(), EngineState::completed) << engine.error();

  const tocd::db::Reader r(path_);
  const auto channels = r.channels(run);
  ASSERT_EQ(channels.size(), expected.size());
  for (std::size_t k = 0; k < channels.size(); ++k) {
    SCOPED_TRACE(expected[k].name);
    EXPECT_EQ(channels[k].name, expected[k].name);
    EXPECT_EQ(channels[k].unit, expected[k].unit);
    EXPECT_EQ(channels[k].nominal_rate_Hz, expected[k].rate_Hz);
    const auto instrument = r.instrument(channels[k].instrument_id);
    ASSERT_TRUE(instrument.has_value());
    EXPECT_EQ(instrument->kind, expected[k].kind);
  }
  // Every described channel was recorded at each step.
  for (const auto& c : channels) EXPECT_GT(r.samples(c.id).size(), 0u) << c.name;
}

namespace {

/// The fake tester under a capability table that names its channels otherwise, as a driver
/// of another instrument kind would.
class MisdescribedTester : public ForwardingTester {
 public:
  using ForwardingTester::ForwardingTester;
  const tocd::devices::InstrumentCapabilities& describe() const override { return kCaps; }

 private:
  static constexpr std::array<tocd::devices::ChannelCapability, 1> kChannels{
      {{"position", "mm", 0, 50, 100}}};
  static constexpr tocd::devices::InstrumentCapabilities kCaps{"mechanical_tester", "mechanical tester",
                                                               kChannels};
};

}  // namespace

TEST_F(EngineTest, ADriverDescribingOtherChannelsIsRefusedNamingBoth) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(path_);
  InstrumentSet set = make_fake_instruments(world);
  set.tester = std::make_unique<MisdescribedTester>(std::move(set.tester));
  try {
    Engine engine(db, std::move(set), fast());
    FAIL() << "an engine was made over a tester that describes no displacement and no load";
  } catch (const EngineError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("[position]"), std::string::npos) << what;
    EXPECT_NE(what.find("[displacement, load]"), std::string::npos) << what;
  }
  EXPECT_TRUE(tocd::db::Reader(path_).runs().empty());
}

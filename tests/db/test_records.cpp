// Round trips: every record written through Database comes back equal through Reader.
#include <cmath>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_database.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/version.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/writer.hpp"

namespace {

using namespace tocd::db;
using tocd::db::testing::prediction_of;
using tocd::db::testing::TestDatabase;

NewRun sample_run() {
  NewRun r;
  r.name = "pin 1.5 mm, \"left\" flank";
  r.protocol_text = "[[steps]]\ndisplacement_mm = 0.25\n# unicode: µm, °C\n";
  r.lab_config_text = "[tester]\ntransport = \"modbus-tcp\"\n";
  r.operator_name = "A. Operator";
  r.baseline_power_W = 1.25e-3;
  return r;
}

TEST(DbRecords, RunRoundTripWithAnchorsAndUuid) {
  TestDatabase dir;
  Database db(dir.location());
  const auto before_mono = tocd::monotonic_ns();
  const auto before_wall = tocd::wall_clock_ns();
  const RunRecord r = db.create_run(sample_run());
  const auto after_wall = tocd::wall_clock_ns();
  EXPECT_GT(r.id, 0);
  EXPECT_EQ(r.status, RunStatus::running);
  EXPECT_EQ(r.software_version, std::string(tocd::version()));
  EXPECT_THAT(r.uuid,
              ::testing::MatchesRegex("[0-9a-f]{8}-[0-9a-f]{4}-4[0-9a-f]{3}-[89ab][0-9a-f]{3}-[0-9a-f]{12}"));
  EXPECT_GE(r.monotonic_anchor_ns, before_mono);
  EXPECT_GE(r.wall_anchor_utc_ns, before_wall);
  EXPECT_LE(r.wall_anchor_utc_ns, after_wall);
  EXPECT_NE(db.create_run(sample_run()).uuid, r.uuid);

  Reader rd(dir.location());
  const RunRecord back = rd.run(r.id);
  EXPECT_EQ(back.uuid, r.uuid);
  EXPECT_EQ(back.name, r.name);
  EXPECT_EQ(back.protocol_text, r.protocol_text);
  EXPECT_EQ(back.lab_config_text, r.lab_config_text);
  EXPECT_EQ(back.operator_name, r.operator_name);
  EXPECT_DOUBLE_EQ(back.baseline_power_W, 1.25e-3);
  EXPECT_EQ(back.wall_anchor_utc_ns, r.wall_anchor_utc_ns);
  EXPECT_EQ(back.monotonic_anchor_ns, r.monotonic_anchor_ns);
  EXPECT_FALSE(back.ended_utc_ns.has_value());
  // The anchor converts a monotonic time one second later to one second later in UTC.
  EXPECT_EQ(back.to_utc_ns(r.monotonic_anchor_ns + 1'000'000'000), r.wall_anchor_utc_ns + 1'000'000'000);
  const auto anchors = rd.anchors(r.id);
  ASSERT_EQ(anchors.size(), 1u);
  EXPECT_EQ(anchors[0].segment, 0);
  EXPECT_EQ(anchors[0].monotonic_ns, r.monotonic_anchor_ns);
  EXPECT_FALSE(rd.find_run(9999).has_value());
  EXPECT_THROW(rd.run(9999), DatabaseError);

  db.set_run_status(r.id, RunStatus::completed);
  const RunRecord done = rd.run(r.id);
  EXPECT_EQ(done.status, RunStatus::completed);
  ASSERT_TRUE(done.ended_utc_ns.has_value());
  EXPECT_GE(*done.ended_utc_ns, done.started_utc_ns);
  EXPECT_THROW(db.set_run_status(r.id, RunStatus::running), DatabaseError);
  EXPECT_THROW(db.set_run_status(4242, RunStatus::completed), DatabaseError);
}

TEST(DbRecords, InstrumentsAreUpsertedBySerialAndSpecimensStored) {
  TestDatabase dir;
  Database db(dir.location());
  const auto a = db.add_instrument({0, "power_meter", "PM100D", "P0012345", "2.1", "2025-01-10 cert 77"});
  const auto b = db.add_instrument({0, "power_meter", "PM100D", "P0012345", "2.2", "2026-01-10 cert 91"});
  const auto c = db.add_instrument({0, "mechanical_tester", "5943", "T-1", "", ""});
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  const auto sp = db.add_sample({0, "S-17", "porcine skin, abdomen", 2.1, "frozen once"});
  Reader rd(dir.location());
  const auto in = rd.instrument(a);
  ASSERT_TRUE(in.has_value());
  EXPECT_EQ(in->firmware, "2.2");
  EXPECT_EQ(in->calibration, "2026-01-10 cert 91");
  EXPECT_EQ(rd.instruments().size(), 2u);
  const auto s = rd.sample(sp);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->tissue, "porcine skin, abdomen");
  EXPECT_DOUBLE_EQ(s->thickness_mm, 2.1);
  EXPECT_EQ(s->notes, "frozen once");
  // A run refers to its specimen.
  NewRun nr = sample_run();
  nr.sample_id = sp;
  EXPECT_EQ(rd.run(db.create_run(nr).id).sample_id, sp);
}

// The first step of a run, completed, with both channels' statistics.
StepRecord completed_step(std::int64_t run, std::int64_t load, std::int64_t power) {
  return {.run_id = run,
          .index = 0,
          .target_displacement_mm = 0.25,
          .nominal_strain = 0.1,
          .started_t_ns = 100,
          .settled_t_ns = 200,
          .recorded_from_t_ns = 300,
          .recorded_to_t_ns = 400,
          .measured_transmission = 0.4125,
          .channels = {{load, 1.5, 0.01, 1000}, {power, 5.1e-4, 1e-6, 10}}};
}

PredictionRecord first_step_prediction(std::int64_t run) {
  return {.run_id = run,
          .step_index = 0,
          .config_json = R"({"photons":100000,"seed":1})",
          .T = 0.40,
          .T_stderr = 0.004,
          .fe_seconds = 1.5,
          .mesh_seconds = 0.5,
          .mc_seconds = 3.0,
          .total_seconds = 5.0,
          .latency_s = 7.25,
          .software_version = {},  // this build's
          .summary_json = R"({"tets":12345})"};
}

// Only a run's own prediction queue measures a latency: a prediction stored without one (a
// re-prediction, an older tocdlab's) reads back unset, never 0.
TEST(DbRecords, PredictionLatencyRoundTripsAndUnsetStaysUnset) {
  TestDatabase dir;
  Database db(dir.location());
  const auto run = db.create_run(sample_run());
  PredictionRecord timed = prediction_of(run.id, 0, "{}", 0.4);
  timed.latency_s = 0.125;
  db.add_prediction(timed);
  db.add_prediction(prediction_of(run.id, 1, "{}", 0.3));

  const auto preds = Reader(dir.location()).predictions(run.id);
  ASSERT_EQ(preds.size(), 2u);
  EXPECT_DOUBLE_EQ(preds[0].latency_s, 0.125);
  EXPECT_TRUE(std::isnan(preds[1].latency_s)) << preds[1].latency_s;
}

TEST(DbRecords, ChannelsStepsEventsPredictionsRoundTrip) {
  TestDatabase dir;
  Database db(dir.location());
  const auto run = db.create_run(sample_run());
  const auto inst = db.add_instrument({0, "mechanical_tester", "5943", "T-1", "", ""});
  const Channel load = db.add_channel({0, run.id, "load", "N", inst, 1000.0});
  const Channel power = db.add_channel({0, run.id, "power", "W", 0, 10.0});
  EXPECT_GT(load.id, 0);
  EXPECT_THROW(db.add_channel({0, run.id, "load", "N", 0, 1.0}), DatabaseError);  // duplicate name
  EXPECT_THROW(db.add_channel({0, 777, "x", "", 0, 1.0}), DatabaseError);         // no such run

  const StepRecord st = completed_step(run.id, load.id, power.id);
  db.add_step(st);
  // Unset doubles (NaN) come back NaN, not 0.
  StepRecord st1 = st;
  st1.index = 1;
  st1.measured_transmission = kUnset;
  st1.completed = false;
  st1.channels = {{load.id, 2.0, kUnset, 1}};
  db.add_step(st1);

  EventRecord ev{0, run.id, 250, "fault", "power meter timeout, retry 1/2", 0, R"({"retry":1})"};
  db.add_event(ev);
  db.add_event({0, run.id, 50, "state", "running", -1, ""});

  const PredictionRecord p = first_step_prediction(run.id);
  db.add_prediction(p);

  Reader rd(dir.location());
  const auto chans = rd.channels(run.id);
  ASSERT_EQ(chans.size(), 2u);
  EXPECT_EQ(chans[0].name, "load");
  EXPECT_EQ(chans[0].unit, "N");
  EXPECT_EQ(chans[0].instrument_id, inst);
  EXPECT_DOUBLE_EQ(chans[0].nominal_rate_Hz, 1000.0);
  EXPECT_EQ(chans[1].instrument_id, 0);
  EXPECT_EQ(rd.channel(run.id, "power")->id, power.id);
  EXPECT_FALSE(rd.channel(run.id, "pressure").has_value());

  const auto steps = rd.steps(run.id);
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[0].settled_t_ns, 200);
  EXPECT_EQ(steps[0].recorded_to_t_ns, 400);
  EXPECT_DOUBLE_EQ(steps[0].measured_transmission, 0.4125);
  EXPECT_TRUE(std::isnan(steps[0].target_pressure_kPa));
  ASSERT_EQ(steps[0].channels.size(), 2u);
  EXPECT_DOUBLE_EQ(steps[0].stats_for(load.id)->mean, 1.5);
  EXPECT_EQ(steps[0].stats_for(power.id)->n, 10);
  EXPECT_FALSE(steps[1].completed);
  EXPECT_TRUE(std::isnan(steps[1].measured_transmission));
  EXPECT_TRUE(std::isnan(steps[1].stats_for(load.id)->std));
  EXPECT_EQ(rd.first_incomplete_step(run.id), 1);

  const auto events = rd.events(run.id);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].t_ns, 50);  // ordered by time, not insertion
  EXPECT_EQ(events[0].step_index, -1);
  EXPECT_EQ(events[1].kind, "fault");
  EXPECT_EQ(events[1].step_index, 0);
  EXPECT_EQ(events[1].data_json, R"({"retry":1})");

  const auto preds = rd.predictions(run.id);
  ASSERT_EQ(preds.size(), 1u);
  EXPECT_EQ(preds[0].config_json, p.config_json);
  EXPECT_DOUBLE_EQ(preds[0].T_stderr, 0.004);
  EXPECT_DOUBLE_EQ(preds[0].mc_seconds, 3.0);
  EXPECT_DOUBLE_EQ(preds[0].latency_s, 7.25);
  EXPECT_EQ(preds[0].software_version, std::string(tocd::version()));
  EXPECT_GT(preds[0].created_utc_ns, run.started_utc_ns - 1);

  // Step 1 was cut short: compare lists completed steps only.
  const auto cmp = rd.compare(run.id);
  ASSERT_EQ(cmp.size(), 1u);
  ASSERT_TRUE(cmp[0].prediction.has_value());
  EXPECT_NEAR(cmp[0].relative_difference, (0.40 - 0.4125) / 0.4125, 1e-15);

  const auto list = rd.runs();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].steps, 2);
  EXPECT_EQ(list[0].predictions, 1);
  EXPECT_EQ(list[0].events, 2);
  EXPECT_TRUE(list[0].live);
}

TEST(DbRecords, ReAddedStepReplacesTheOldOneAndLatestPredictionWins) {
  TestDatabase dir;
  Database db(dir.location());
  const auto run = db.create_run(sample_run());
  const Channel load = db.add_channel({0, run.id, "load", "N", 0, kUnset});
  StepRecord st;
  st.run_id = run.id;
  st.index = 3;
  st.completed = false;
  st.channels = {{load.id, 1.0, 0.1, 5}};
  db.add_step(st);
  st.completed = true;
  st.measured_transmission = 0.5;
  st.channels = {{load.id, 2.0, 0.2, 50}};
  db.add_step(st);
  PredictionRecord p = prediction_of(run.id, 3, "{}", 0.45);
  db.add_prediction(p);
  p.T = 0.55;
  db.add_prediction(p);
  Reader rd(dir.location());
  const auto steps = rd.steps(run.id);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_TRUE(steps[0].completed);
  ASSERT_EQ(steps[0].channels.size(), 1u);
  EXPECT_EQ(steps[0].channels[0].n, 50);
  const auto cmp = rd.compare(run.id);
  ASSERT_EQ(cmp.size(), 1u);
  EXPECT_DOUBLE_EQ(cmp[0].prediction->T, 0.55);
  EXPECT_NEAR(cmp[0].relative_difference, 0.1, 1e-12);
  // Step statistics must name channels that exist.
  st.channels = {{9999, 1.0, 0.1, 5}};
  EXPECT_THROW(db.add_step(st), DatabaseError);
  EXPECT_EQ(rd.steps(run.id)[0].channels[0].n, 50);  // the failed replace rolled back
}

TEST(DbRecords, RunStatusText) {
  for (auto s : {RunStatus::running, RunStatus::completed, RunStatus::aborted, RunStatus::interrupted})
    EXPECT_EQ(run_status_from_string(to_string(s)), s);
  EXPECT_THROW(run_status_from_string("paused"), DatabaseError);
}

}  // namespace

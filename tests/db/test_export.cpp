// CSV and JSON export of a run: every stored value appears, in the documented columns/keys.
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_database.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/export.hpp"
#include "tocd/db/writer.hpp"

namespace {

using namespace tocd::db;
using tocd::db::testing::prediction_of;
using tocd::db::testing::TestDatabase;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::string cur;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\r') ADD_FAILURE() << "CR in the CSV at byte " << i << ": lines end in LF";
    if (text[i] == '\n') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += text[i];
    }
  }
  EXPECT_TRUE(cur.empty()) << "last line must end with LF";
  return out;
}

class DbExport : public ::testing::Test {
 protected:
  void SetUp() override {
    Database db(path_);
    const auto sp = db.add_sample({0, "S-1", "porcine skin", 2.0, ""});
    NewRun nr;
    nr.name = "export run";
    nr.sample_id = sp;
    nr.protocol_text = "[sample]\nthickness_mm = 2.0\n";
    nr.baseline_power_W = 1e-3;
    run_ = db.create_run(nr);
    const auto inst = db.add_instrument({0, "mechanical_tester", "5943", "T-1", "1.0", ""});
    load_ = db.add_channel({0, run_.id, "load", "N", inst, 1000.0});
    power_ = db.add_channel({0, run_.id, "power", "W", 0, 10.0});
    {
      Writer w(db);
      for (int i = 0; i < 50; ++i) w.enqueue(Sample{load_.id, t(i), 0.1 * i});
      for (int i = 0; i < 5; ++i) w.enqueue(Sample{power_.id, t(10 * i), 5e-4});
    }
    StepRecord st;
    st.run_id = run_.id;
    st.index = 0;
    st.target_displacement_mm = 0.5;
    st.nominal_strain = 0.25;
    st.settled_t_ns = t(10);
    st.recorded_from_t_ns = t(10);
    st.recorded_to_t_ns = t(49);
    st.measured_transmission = 0.5;
    st.channels = {{load_.id, 2.95, 1.2, 40}, {power_.id, 5e-4, 0.0, 4}};
    db.add_step(st);
    st.index = 1;
    st.completed = false;
    st.measured_transmission = kUnset;
    st.channels = {};
    db.add_step(st);
    db.add_event({0, run_.id, t(5), "operator", "note, with \"quotes\"\nand a line break", 0, ""});
    db.add_prediction(prediction_of(run_.id, 0, R"({"photons":1000,"seed":7})", 0.375, 0.01));
    db.set_run_status(run_.id, RunStatus::completed);
  }
  std::int64_t t(int i) const { return run_.monotonic_anchor_ns + 1'000'000LL * i; }  // 1 kHz

  TestDatabase dir_;
  std::filesystem::path path_ = dir_.location();
  RunRecord run_;
  Channel load_, power_;
};

TEST_F(DbExport, StepsCsvHasOneRowPerStepWithStatsAndPrediction) {
  std::ostringstream out;
  write_csv(Reader(path_), run_.id, CsvTable::steps, out);
  const auto l = lines(out.str());
  // Step 2 was cut short: not a measurement, so not a row.
  ASSERT_EQ(l.size(), 2u);
  EXPECT_EQ(
      l[0],
      "step,completed,target_displacement_mm,nominal_strain,target_pressure_kPa,settled_s,recorded_from_s,"
      "recorded_to_s,load_mean_N,load_std_N,load_n,power_mean_W,power_std_W,power_n,measured_T,measured_T_se,"
      "predicted_T,predicted_T_se,relative_difference");
  // Steps are numbered from 1; measured_T_se = power std / sqrt(n) / baseline = 0 / 2 / 1e-3.
  EXPECT_EQ(l[1], "1,1,0.5,0.25,,0.010000,0.010000,0.049000,2.95,1.2,40,0.0005,0,4,0.5,0,0.375,0.01,-0.25");
}

TEST_F(DbExport, SamplesCsvIsLongFormatWithUtc) {
  std::ostringstream out;
  write_csv(Reader(path_), run_.id, CsvTable::samples, out);
  const auto l = lines(out.str());
  ASSERT_EQ(l.size(), 1u + 50u + 5u);
  EXPECT_EQ(l[0], "t_ns,segment,t_s,utc,channel,unit,value");
  EXPECT_EQ(l[4], std::to_string(t(3)) + ",0,0.003000000," +
                      tocd::format_utc(run_.wall_anchor_utc_ns + 3'000'000) + ",load,N,0.30000000000000004");
  EXPECT_THAT(l[51], ::testing::EndsWith(",power,W,0.0005"));
}

TEST_F(DbExport, EventsCsvQuotesCommasQuotesAndLineBreaks) {
  std::ostringstream out;
  write_csv(Reader(path_), run_.id, CsvTable::events, out);
  const std::string text = out.str();
  EXPECT_THAT(text, ::testing::HasSubstr(",operator,1,\"note, with \"\"quotes\"\"\nand a line break\"\n"));
}

TEST_F(DbExport, JsonHoldsTheWholeRun) {
  std::ostringstream out;
  write_json(Reader(path_), run_.id, {}, out);
  const auto j = nlohmann::json::parse(out.str());
  EXPECT_EQ(j["format"], "tocdlab-run");
  EXPECT_EQ(j["run"]["uuid"], run_.uuid);
  EXPECT_EQ(j["run"]["status"], "completed");
  EXPECT_EQ(j["run"]["protocol"], "[sample]\nthickness_mm = 2.0\n");
  EXPECT_EQ(j["run"]["started_utc"], tocd::format_utc(run_.started_utc_ns));
  EXPECT_EQ(j["sample"]["tissue"], "porcine skin");
  EXPECT_EQ(j["instruments"].size(), 1u);
  EXPECT_EQ(j["instruments"][0]["model"], "5943");
  ASSERT_EQ(j["channels"].size(), 2u);
  const auto& load = j["channels"][0];
  EXPECT_EQ(load["name"], "load");
  EXPECT_EQ(load["sample_count"], 50);
  ASSERT_EQ(load["t_ns"].size(), 50u);
  EXPECT_EQ(load["t_ns"][7].get<std::int64_t>(), t(7));
  EXPECT_DOUBLE_EQ(load["value"][7].get<double>(), 0.1 * 7);
  EXPECT_TRUE(j["channels"][1]["instrument_id"].is_null());
  ASSERT_EQ(j["steps"].size(), 1u);  // step 2 was cut short: not a measurement
  EXPECT_DOUBLE_EQ(j["steps"][0]["predicted_T"].get<double>(), 0.375);
  EXPECT_DOUBLE_EQ(j["steps"][0]["relative_difference"].get<double>(), -0.25);
  EXPECT_TRUE(j["steps"][0]["target_pressure_kPa"].is_null());
  ASSERT_EQ(j["predictions"].size(), 1u);
  EXPECT_EQ(j["predictions"][0]["config"]["seed"], 7);  // stored JSON is embedded, not quoted
  ASSERT_EQ(j["events"].size(), 1u);
  EXPECT_EQ(j["events"][0]["utc"], tocd::format_utc(run_.wall_anchor_utc_ns + 5'000'000));
}

TEST_F(DbExport, JsonGivesEachPredictionItsLatencyNullWhenUnset) {
  PredictionRecord timed = prediction_of(run_.id, 0, "{}", 0.375, 0.01);
  timed.latency_s = 0.5;
  Database(path_).add_prediction(timed);
  std::ostringstream out;
  write_json(Reader(path_), run_.id, {}, out);
  const auto j = nlohmann::json::parse(out.str());
  ASSERT_EQ(j["predictions"].size(), 2u);
  ASSERT_TRUE(j["predictions"][0].contains("latency_s"));
  EXPECT_TRUE(j["predictions"][0]["latency_s"].is_null());  // stored without one
  EXPECT_DOUBLE_EQ(j["predictions"][1]["latency_s"].get<double>(), 0.5);
}

TEST_F(DbExport, JsonCanDecimateOrOmitSamples) {
  std::ostringstream dec, none;
  write_json(Reader(path_), run_.id, {true, 10, -1}, dec);
  const auto j = nlohmann::json::parse(dec.str());
  EXPECT_LE(j["channels"][0]["t_ns"].size(), 10u);
  EXPECT_EQ(j["channels"][0]["decimated"], true);
  EXPECT_EQ(j["channels"][1]["decimated"], false);  // 5 samples fit
  write_json(Reader(path_), run_.id, {false, 0, -1}, none);
  const auto k = nlohmann::json::parse(none.str());
  EXPECT_FALSE(k["channels"][0].contains("t_ns"));
  EXPECT_EQ(k["channels"][0]["sample_count"], 50);
}

TEST_F(DbExport, JsonSurvivesInvalidUtf8InStoredStrings) {
  // A file written before instrument strings were cleaned, or by something else: the same
  // instrument (model, serial) with firmware bytes that are not UTF-8 and an ESC.
  Database(path_).add_instrument({0, "mechanical_tester", "5943", "T-1", "1.0\xFF\x1B[2J", ""});
  std::ostringstream out;
  ASSERT_NO_THROW(write_json(Reader(path_), run_.id, {}, out));
  EXPECT_EQ(out.str().find('\x1B'), std::string::npos);  // control characters are escaped
  const auto j = nlohmann::json::parse(out.str());
  EXPECT_EQ(j["instruments"][0]["firmware"], "1.0\xEF\xBF\xBD\x1B[2J");
}

TEST_F(DbExport, UnknownRunIsAnError) {
  std::ostringstream out;
  EXPECT_THROW(write_csv(Reader(path_), 99, CsvTable::steps, out), DatabaseError);
  EXPECT_THROW(write_json(Reader(path_), 99, {}, out), DatabaseError);
}

}  // namespace

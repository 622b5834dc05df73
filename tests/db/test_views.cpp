// The views pandas reads (sample_series, step_comparison, measurements), the export's UTC per
// resume segment, and the metadata stored with a run.
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "raw_sqlite.hpp"
#include "test_database.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/version.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/export.hpp"
#include "tocd/db/writer.hpp"
#include "tocd/test/temp_dir.hpp"

namespace {

using namespace tocd::db;
using tocd::db::testing::prediction_of;
using tocd::db::testing::raw_rows;
using tocd::test::TempDir;

// The wall clock was stepped by this much between the run's first segment and its resume
// (an NTP correction, or the machine's clock set by hand): UTC after the resume must follow
// the resume's own anchor, not the first one.
constexpr std::int64_t kWallStepNs = 3'600'000'000'000LL + 123'456'789LL;

class DbViews : public ::testing::Test {
 protected:
  void SetUp() override {
    Database db(path_);
    NewRun nr;
    nr.name = "views run";
    nr.baseline_power_W = 2e-3;
    nr.settings = {{"power_meter.sensor", "S121C, 123"}, {"power_meter.wavelength_nm", "635"}};
    run_ = db.create_run(nr);
    disp_ = db.add_channel({0, run_.id, "displacement", "mm", 0, 100.0});
    power_ = db.add_channel({0, run_.id, "power", "W", 0, 100.0});
    {
      Writer w(db);
      for (int i = 0; i < 10; ++i)
        w.enqueue(Sample{power_.id, run_.monotonic_anchor_ns + 1'000'000LL * i, 1e-3});
    }
    StepRecord st;  // step 0: completed, measured and predicted
    st.run_id = run_.id;
    st.index = 0;
    st.target_displacement_mm = 0.5;
    st.started_t_ns = run_.monotonic_anchor_ns + 1;
    st.measured_transmission = 0.5;
    st.channels = {{disp_.id, 0.498, 0.001, 25}, {power_.id, 1e-3, 4e-5, 16}};
    db.add_step(st);
    st.index = 1;  // step 1: cut short by the interruption
    st.target_displacement_mm = 1.0;
    st.completed = false;
    st.measured_transmission = 0.4;
    st.channels = {{disp_.id, 0.7, 0.1, 5}, {power_.id, 8e-4, 1e-5, 3}};
    db.add_step(st);
    PredictionRecord p = prediction_of(run_.id, 0, "{}", 0.45, 0.02);
    db.add_prediction(p);
    p.T = 0.55;  // a later prediction of the same step supersedes the first
    p.T_stderr = 0.01;
    db.add_prediction(p);
    db.set_run_status(run_.id, RunStatus::interrupted);
    // The samples above are stamped up to 9 ms after the anchor: resume after that, as a real
    // resume always comes after what was recorded.
    while (tocd::monotonic_ns() <= run_.monotonic_anchor_ns + 10'000'000LL) {
    }

    resume_ = db.resume_run(run_.id);
    {
      Writer w(db);
      for (int i = 0; i < 5; ++i) w.enqueue(Sample{power_.id, resume_.gap_to_t_ns + 1'000'000LL * i, 9e-4});
    }
    db.add_event({0, run_.id, resume_.gap_to_t_ns + 2'000'000, "operator", "after resume", 1, ""});
    db.set_run_status(run_.id, RunStatus::completed);
    ASSERT_EQ(
        tocd::db::testing::raw_exec(
            path_,
            fmt::format(
                "UPDATE run_anchors SET wall_utc_ns = wall_utc_ns + {} WHERE run_id = {} AND segment = 1",
                kWallStepNs, run_.id)),
        "");
    anchors_ = Reader(path_).anchors(run_.id);
  }

  // UTC of a time recorded in `segment`, computed here from the stored anchor pair.
  std::int64_t expected_utc(int segment, std::int64_t t_ns) const {
    const RunAnchor& a = anchors_.at(static_cast<std::size_t>(segment));
    return a.wall_utc_ns + (t_ns - a.monotonic_ns);
  }

  TempDir dir_{"db_views"};
  std::filesystem::path path_ = dir_ / "lab.sqlite";
  RunRecord run_;
  ResumePoint resume_;
  Channel disp_, power_;
  std::vector<RunAnchor> anchors_;
};

TEST_F(DbViews, SampleSeriesTakesEachSamplesUtcFromItsOwnSegment) {
  ASSERT_EQ(anchors_.size(), 2u);
  const auto rows =
      raw_rows(path_, fmt::format("SELECT segment, t_ns, utc_ns, t_s, utc, channel, unit, value "
                                  "FROM sample_series WHERE run_id = {} ORDER BY utc_ns",
                                  run_.id));
  ASSERT_EQ(rows.size(), 15u);
  for (const auto& r : rows) {
    const int segment = std::stoi(r[0]);
    const std::int64_t t = std::stoll(r[1]);
    EXPECT_EQ(segment, t >= resume_.gap_to_t_ns ? 1 : 0) << "t_ns " << t;
    EXPECT_EQ(std::stoll(r[2]), expected_utc(segment, t));
    EXPECT_NEAR(std::stod(r[3]), static_cast<double>(expected_utc(segment, t) - run_.started_utc_ns) * 1e-9,
                1e-9);
    EXPECT_EQ(r[4].substr(0, 23), tocd::format_utc(expected_utc(segment, t)).substr(0, 23));
    EXPECT_EQ(r[5], "power");
    EXPECT_EQ(r[6], "W");
  }
  // The first sample after the resume lies the wall-clock step after the last one before it.
  const std::int64_t before = std::stoll(rows[9][2]), after = std::stoll(rows[10][2]);
  EXPECT_GE(after - before, kWallStepNs);
}

TEST_F(DbViews, StepComparisonListsEveryStepAndMeasurementsOnlyCompletedOnes) {
  const auto all = raw_rows(path_, fmt::format("SELECT step, state, target_displacement_mm, displacement_mm, "
                                               "measured_T, measured_T_se, predicted_T, predicted_T_se "
                                               "FROM step_comparison WHERE run_id = {} ORDER BY step",
                                               run_.id));
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0][0], "1");  // steps are 1-based outside the storage
  EXPECT_EQ(all[0][1], "completed");
  EXPECT_DOUBLE_EQ(std::stod(all[0][2]), 0.5);
  EXPECT_DOUBLE_EQ(std::stod(all[0][3]), 0.498);
  EXPECT_DOUBLE_EQ(std::stod(all[0][4]), 0.5);
  // SE of the mean power (std / sqrt(n)) relative to the baseline: 4e-5 / 4 / 2e-3 = 0.005.
  EXPECT_NEAR(std::stod(all[0][5]), 0.005, 1e-15);
  EXPECT_DOUBLE_EQ(std::stod(all[0][6]), 0.55);  // the latest prediction
  EXPECT_DOUBLE_EQ(std::stod(all[0][7]), 0.01);
  EXPECT_EQ(all[1][0], "2");
  EXPECT_EQ(all[1][1], "incomplete");
  EXPECT_DOUBLE_EQ(std::stod(all[1][2]), 1.0);
  for (int c : {3, 4, 5}) EXPECT_EQ(all[1][static_cast<std::size_t>(c)], "NULL") << "column " << c;

  const auto measured = raw_rows(
      path_,
      fmt::format("SELECT step, measured_T, predicted_T FROM measurements WHERE run_id = {}", run_.id));
  ASSERT_EQ(measured.size(), 1u);
  EXPECT_EQ(measured[0][0], "1");
}

TEST_F(DbViews, SamplesAndEventsCsvUseTheResumeAnchorAfterAResume) {
  std::ostringstream samples, events;
  const Reader reader(path_);
  write_csv(reader, run_.id, CsvTable::samples, samples);
  write_csv(reader, run_.id, CsvTable::events, events);
  const std::string after = tocd::format_utc(expected_utc(1, resume_.gap_to_t_ns + 3'000'000));
  EXPECT_THAT(samples.str(), ::testing::HasSubstr(fmt::format("{},1,", resume_.gap_to_t_ns + 3'000'000)));
  EXPECT_THAT(samples.str(), ::testing::HasSubstr("," + after + ",power,W,0.0009\n"));
  EXPECT_THAT(events.str(), ::testing::HasSubstr(fmt::format(
                                "{},1,{},operator,2,after resume\n", resume_.gap_to_t_ns + 2'000'000,
                                tocd::format_utc(expected_utc(1, resume_.gap_to_t_ns + 2'000'000)))));
  EXPECT_EQ(samples.str().find('\r'), std::string::npos);
}

TEST_F(DbViews, RunCarriesHostSoftwareCommitAndInstrumentSettings) {
  char host[256] = {};
  ASSERT_EQ(::gethostname(host, sizeof host - 1), 0);
  const RunRecord r = Reader(path_).run(run_.id);
  EXPECT_EQ(r.host, host);
  EXPECT_EQ(r.software_commit, tocd::git_commit());
  EXPECT_FALSE(r.software_commit.empty());
  EXPECT_EQ(r.settings.at("power_meter.wavelength_nm"), "635");
  EXPECT_EQ(r.settings.at("power_meter.sensor"), "S121C, 123");
  EXPECT_EQ(Reader(path_).runs().at(0).run.settings.size(), 2u);

  std::ostringstream out;
  write_json(Reader(path_), run_.id, {}, out);
  const auto j = nlohmann::json::parse(out.str());
  EXPECT_EQ(j["run"]["host"], host);
  EXPECT_EQ(j["run"]["software_commit"], std::string(tocd::git_commit()));
  EXPECT_EQ(j["run"]["settings"]["power_meter.wavelength_nm"], "635");
  EXPECT_EQ(j["channels"][1]["segment"].back(), 1);
  EXPECT_EQ(j["events"].back()["utc"], tocd::format_utc(expected_utc(1, resume_.gap_to_t_ns + 2'000'000)));
}

// docs/database.md's pandas example, run as written by Debian's python3-pandas.
TEST_F(DbViews, PandasExampleOfTheDocsReadsTheViews) {
  const std::int64_t t = resume_.gap_to_t_ns + 3'000'000;
  const std::string cmd = fmt::format("{} {} {} {} {} {} {}", TOCD_SYSTEM_PYTHON, TOCD_PANDAS_CHECK,
                                      TOCD_DATABASE_MD, path_.string(), run_.id, expected_utc(1, t), 1);
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

}  // namespace

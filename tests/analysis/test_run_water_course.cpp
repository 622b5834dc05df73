// analysis::run_water_course's pieces on a small hand-made run: the displacement history
// taken from the record, the measured T around a time, clear errors.
#include <cmath>

#include <gtest/gtest.h>

#include "tocd/analysis/run_water_course.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/database.hpp"
#include "water_course_run.hpp"

namespace {

using namespace water_course_test;
namespace an = tocd::analysis;

TEST_F(RunWaterCourse, TheHistoryFollowsEveryRecordedSampleWithFewKnots) {
  const auto run = write_run();
  const tocd::db::Reader reader(path_.string());
  const auto h = an::displacement_history_from_run(reader, run, kT0 + 9 * kSecond, 1e-4);
  EXPECT_EQ(h.t0_ns, kT0);
  EXPECT_EQ(h.samples, 901u) << "samples up to 9 s inclusive";
  // Corners of the program: 0 (start), 0.3 (approach ends), 2, 2.5, 6, 6.5, 9 (end), give or take
  // the sample next to a corner that lies between samples.
  EXPECT_LE(h.history.t_s.size(), 12u);
  EXPECT_GE(h.history.t_s.size(), 6u);
  for (const auto& [t, d] : recorded_) {
    if (t > 9.0 + 1e-9) break;
    EXPECT_NEAR(h.history.at(t), std::max(0.0, d), 1e-4) << "t = " << t;
  }
  EXPECT_EQ(h.history.d_mm.front(), 0.0) << "approach above the surface is no depth";
  EXPECT_NO_THROW(h.history.validate(kThickness));
}

TEST_F(RunWaterCourse, MeasuredTIsTheMeanOfTheStoredPowerInTheWindow) {
  const auto run = write_run();
  const tocd::db::Reader reader(path_.string());
  const auto power = reader.channel(run, "power");
  ASSERT_TRUE(power);
  const auto m = an::measured_T_between(reader, power->id, kBaseline, kT0 + 3 * kSecond, kT0 + 4 * kSecond);
  EXPECT_EQ(m.n, 11);
  EXPECT_NEAR(m.T, mean_T(3.0, 4.0), 1e-12);
  EXPECT_GT(m.se, 0.0);
  const auto none =
      an::measured_T_between(reader, power->id, kBaseline, kT0 + 20 * kSecond, kT0 + 21 * kSecond);
  EXPECT_EQ(none.n, 0);
  EXPECT_TRUE(std::isnan(none.T));
}

TEST_F(RunWaterCourse, AResumedRunIsRefused) {
  const auto run = write_run();
  {
    tocd::db::Database db(path_.string());
    db.set_run_status(run, tocd::db::RunStatus::interrupted);
    db.resume_run(run);
  }
  const tocd::db::Reader reader(path_.string());
  try {
    an::displacement_history_from_run(reader, run, kT0 + 9 * kSecond);
    FAIL();
  } catch (const tocd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("was resumed (2 recording segments)"), std::string::npos)
        << e.what();
  }
}

TEST_F(RunWaterCourse, ARunWithoutAPinHistoryOrWithThePinInTheSkinIsAClearError) {
  {
    const auto run = write_run(true);
    const tocd::db::Reader reader(path_.string());
    try {
      an::displacement_history_from_run(reader, run, kT0 + 9 * kSecond);
      FAIL();
    } catch (const tocd::Error& e) {
      EXPECT_NE(std::string(e.what()).find("starts with the pin"), std::string::npos) << e.what();
    }
  }
  TearDown();
  const auto run = write_run(false, false);
  const tocd::db::Reader reader(path_.string());
  try {
    an::run_water_course(reader, run, {});
    FAIL();
  } catch (const tocd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("no displacement channel"), std::string::npos) << e.what();
  }
}

}  // namespace

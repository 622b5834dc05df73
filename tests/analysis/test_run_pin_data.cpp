// A recorded run as data for the inverse FE fit: the held loads of its steps, or its loading curve.
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "tester_run.hpp"
#include "tocd/analysis/run_pin_data.hpp"
#include "tocd/analysis/run_stress_strain.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"

namespace fs = std::filesystem;
namespace an = tocd::analysis;

namespace {

constexpr double kRunThickness = 2.0, kPinRadius = 1.5;

struct StepSpec {
  double target_mm, reported_mm, load_N;
  bool completed = true;
};

// Steps with their window statistics (what the engine stores), plus a loading curve of
// samples 0 -> deepest target so that the loading branch has data as well.
std::int64_t record_run(const fs::path& path, const std::vector<StepSpec>& steps,
                        bool with_thickness = true) {
  tocd::db::Database db(path.string());
  const auto run = tocd::acquisition::testing::create_tester_run(
      db, with_thickness ? kRunThickness : std::nan(""), "held");
  const auto d_id = run.displacement_channel, l_id = run.load_channel;
  {
    tocd::acquisition::testing::TesterSampleWriter w(db, run);
    for (int i = 1; i <= 1500; ++i) w.put(i * 1e-3, 0.1 * i * 1e-3);
    w.finish();
  }
  for (std::size_t k = 0; k < steps.size(); ++k) {
    tocd::db::StepRecord s;
    s.run_id = run.run_id;
    s.index = static_cast<int>(k);
    s.target_displacement_mm = steps[k].target_mm;
    s.nominal_strain = steps[k].target_mm / kRunThickness;
    s.completed = steps[k].completed;
    s.channels.push_back({d_id, steps[k].reported_mm, 1e-4, 20});
    s.channels.push_back({l_id, steps[k].load_N, 1e-3, 20});
    db.add_step(s);
  }
  db.set_run_status(run.run_id, tocd::db::RunStatus::completed);
  return run.run_id;
}

class RunPinData : public tocd::acquisition::testing::TempDatabaseTest {};

TEST_F(RunPinData, HeldPointsAreEachCompletedStepsMeanLoadAtTheDisplacementTheTesterReported) {
  const auto id = record_run(path_, {{0.0, 0.0, 0.0},
                                     {0.25, 0.2497, 0.004},
                                     {0.5, 0.4991, 0.012},
                                     {0.75, 0.7488, 0.030, false},  // cut short: no measurement
                                     {1.0, 0.9993, 0.050}});
  const auto p =
      an::pin_data_from_run(tocd::db::Reader(path_.string()), id, an::RunLoadPoints::held, kPinRadius);
  ASSERT_EQ(p.displacement_mm.size(), 3u) << "the flat step and the step cut short do not enter";
  EXPECT_DOUBLE_EQ(p.displacement_mm[0], 0.2497);
  EXPECT_DOUBLE_EQ(p.displacement_mm[1], 0.4991);
  EXPECT_DOUBLE_EQ(p.displacement_mm[2], 0.9993);
  EXPECT_DOUBLE_EQ(p.load_N[0], 0.004);
  EXPECT_DOUBLE_EQ(p.load_N[1], 0.012);
  EXPECT_DOUBLE_EQ(p.load_N[2], 0.050);
  EXPECT_DOUBLE_EQ(p.model.thickness_mm, kRunThickness);
  EXPECT_DOUBLE_EQ(p.model.pin_radius_mm, kPinRadius);
  // An explicit thickness replaces the recorded one; the points stay displacements.
  const auto q = an::pin_data_from_run(tocd::db::Reader(path_.string()), id, an::RunLoadPoints::held,
                                       kPinRadius, 16, 2.5);
  EXPECT_DOUBLE_EQ(q.model.thickness_mm, 2.5);
  EXPECT_DOUBLE_EQ(q.displacement_mm[2], 0.9993);
}

TEST_F(RunPinData, LoadingPointsAreTheBinnedLoadingCurveAsLoads) {
  const auto id = record_run(path_, {{0.5, 0.5, 0.05}, {1.0, 1.0, 0.1}});
  const tocd::db::Reader reader(path_.string());
  const auto p = an::pin_data_from_run(reader, id, an::RunLoadPoints::loading, kPinRadius, 10);
  const auto ss = an::stress_strain_from_run(reader, id, kPinRadius, 10);
  ASSERT_EQ(p.displacement_mm.size(), ss.strain.size());
  const double area = std::numbers::pi * kPinRadius * kPinRadius;
  for (std::size_t k = 0; k < ss.strain.size(); ++k) {
    EXPECT_NEAR(p.displacement_mm[k], ss.strain[k] * kRunThickness, 1e-12);
    EXPECT_NEAR(p.load_N[k], ss.stress_MPa[k] * area, 1e-12);
    // The recorded curve is load = 0.1 N/mm x d: each bin's mean pair lies on it.
    EXPECT_NEAR(p.load_N[k], 0.1 * p.displacement_mm[k], 1e-9);
  }
}

TEST_F(RunPinData, HeldLoadsOfARunThatGoesBackAreRefusedNamingTheStep) {
  const auto id = record_run(path_, {{0.5, 0.5, 0.02}, {1.0, 1.0, 0.05}, {0.75, 0.75, 0.03}});
  try {
    an::pin_data_from_run(tocd::db::Reader(path_.string()), id, an::RunLoadPoints::held, kPinRadius);
    FAIL() << "expected an error";
  } catch (const tocd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("step 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--points loading"), std::string::npos) << e.what();
  }
}

TEST_F(RunPinData, TooFewPointsOrNoThicknessAreClearErrors) {
  {
    const auto id = record_run(path_, {{0.0, 0.0, 0.0}, {0.5, 0.5, 0.02}});
    try {
      an::pin_data_from_run(tocd::db::Reader(path_.string()), id, an::RunLoadPoints::held, kPinRadius);
      FAIL() << "expected an error";
    } catch (const tocd::Error& e) {
      EXPECT_NE(std::string(e.what()).find("only 1 held"), std::string::npos) << e.what();
    }
  }
  TearDown();
  const auto id = record_run(path_, {{0.5, 0.5, 0.02}, {1.0, 1.0, 0.05}}, false);
  try {
    an::pin_data_from_run(tocd::db::Reader(path_.string()), id, an::RunLoadPoints::held, kPinRadius);
    FAIL() << "expected an error";
  } catch (const tocd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("thickness"), std::string::npos) << e.what();
  }
}

TEST(RunLoadPoints, NamesRoundTripAndAnUnknownNameIsRefusedByName) {
  for (auto p : {an::RunLoadPoints::held, an::RunLoadPoints::loading})
    EXPECT_EQ(an::parse_run_load_points(an::to_string(p)), p);
  try {
    an::parse_run_load_points("relaxed");
    FAIL() << "expected an error";
  } catch (const tocd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("relaxed"), std::string::npos) << e.what();
  }
}

}  // namespace

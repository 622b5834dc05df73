// Clearing during the holds: T at the start and the end of each step's recording window.
#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "tester_run.hpp"
#include "tocd/acquisition/hold_clearing.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/writer.hpp"

namespace fs = std::filesystem;
namespace acq = tocd::acquisition;

namespace {

constexpr double kBaseline = 2e-3;  // W
constexpr std::int64_t kSecond = 1'000'000'000;

class HoldClearing : public tocd::acquisition::testing::TempDatabaseTest {};

// Two steps recorded over 5 s each at 10 Hz: step 1's power rises linearly (P = P0 (0.2 + 0.01 t)),
// step 2's stays flat; a third step was cut short and is left out.
TEST_F(HoldClearing, MeansOverTheFirstAndLastSecondOfEachWindow) {
  std::int64_t run_id = 0;
  {
    tocd::db::Database db(path_.string());
    tocd::db::NewRun nr;
    nr.name = "holds";
    nr.baseline_power_W = kBaseline;
    run_id = db.create_run(nr).id;
    tocd::db::Channel pc;
    pc.run_id = run_id;
    pc.name = "power";
    pc.unit = "W";
    const auto p_id = db.add_channel(pc).id;
    tocd::db::Writer w(db);
    for (int k = 0; k < 3; ++k) {
      const std::int64_t from = (10 + 20 * k) * kSecond, to = from + 5 * kSecond;
      for (int i = 0; i <= 50; ++i) {
        const double t = 0.1 * i;
        const double P = k == 0 ? kBaseline * (0.2 + 0.01 * t) : 0.5 * kBaseline;
        w.enqueue(tocd::db::Sample{p_id, from + i * kSecond / 10, P});
      }
      tocd::db::StepRecord s;
      s.run_id = run_id;
      s.index = k;
      s.target_displacement_mm = 0.5 * (k + 1);
      s.recorded_from_t_ns = from;
      s.recorded_to_t_ns = to;
      s.completed = k < 2;
      s.measured_transmission = 0.3;
      db.add_step(s);
    }
    w.flush();
    w.stop();
  }
  const tocd::db::Reader reader(path_.string());
  const auto rows = acq::hold_clearing(reader, run_id, 1.0);
  ASSERT_EQ(rows.size(), 2u);
  // Samples at t = 0.0 ... 1.0 s (11, both ends inclusive): mean t 0.5 s -> T 0.205; the last
  // second t = 4.0 ... 5.0 s: mean 4.5 s -> T 0.245.
  EXPECT_NEAR(rows[0].T_start, 0.205, 1e-12);
  EXPECT_NEAR(rows[0].T_end, 0.245, 1e-12);
  EXPECT_NEAR(rows[0].dT, 0.04, 1e-12);
  EXPECT_NEAR(rows[0].window_s, 5.0, 1e-12);
  // The standard error of the mean of the first second's 11 values, computed here directly.
  double m = 0, ss = 0;
  for (int i = 0; i <= 10; ++i) m += 0.2 + 0.001 * i;
  m /= 11;
  for (int i = 0; i <= 10; ++i) ss += std::pow(0.2 + 0.001 * i - m, 2);
  EXPECT_NEAR(rows[0].T_start_se, std::sqrt(ss / 10) / std::sqrt(11.0), 1e-12);
  EXPECT_NEAR(rows[1].T_start, 0.5, 1e-12);
  EXPECT_NEAR(rows[1].dT, 0.0, 1e-12);
  EXPECT_EQ(rows[1].index, 1);

  const auto j = acq::hold_clearing_json(rows);
  EXPECT_EQ(j[0]["step"], 1) << "1-based in output";
  EXPECT_NE(acq::format_hold_clearing(rows).find("+0.0400"), std::string::npos);
}

TEST_F(HoldClearing, ARunWithoutPowerOrBaselineIsAClearError) {
  std::int64_t run_id = 0;
  {
    tocd::db::Database db(path_.string());
    tocd::db::NewRun nr;
    nr.name = "no power";
    run_id = db.create_run(nr).id;
  }
  const tocd::db::Reader reader(path_.string());
  try {
    acq::hold_clearing(reader, run_id);
    FAIL();
  } catch (const tocd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("no power channel"), std::string::npos) << e.what();
  }
}

}  // namespace

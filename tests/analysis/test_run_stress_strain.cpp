// Nominal stress-strain data from a recorded run (the input of `tocdlab fit --db`).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "tester_run.hpp"
#include "tocd/analysis/run_stress_strain.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"

namespace fs = std::filesystem;
namespace an = tocd::analysis;

namespace {

constexpr double kThickness = 2.0, kRadius = 1.5;
double load_of(double d) {
  return 0.05 * d * d + 0.01 * d;
}

// A run whose pin goes 0 -> 1.2 mm (loading), holds with the load relaxing, and retracts.
std::int64_t record_run(const fs::path& path, bool with_thickness) {
  tocd::db::Database db(path.string());
  const auto run = tocd::acquisition::testing::create_tester_run(
      db, with_thickness ? kThickness : std::nan(""), "synthetic");
  tocd::acquisition::testing::TesterSampleWriter w(db, run);
  for (int i = -100; i <= 1200; ++i) w.put(i * 1e-3, i > 0 ? load_of(i * 1e-3) : 0.0);
  for (int i = 0; i < 500; ++i) w.put(1.2, 0.5 * load_of(1.2));  // relaxation while holding: excluded
  for (int i = 1200; i >= 0; i -= 2) w.put(i * 1e-3, 0.2 * load_of(i * 1e-3));  // retraction: excluded
  w.finish();
  db.set_run_status(run.run_id, tocd::db::RunStatus::completed);
  return run.run_id;
}

class RunStressStrain : public tocd::acquisition::testing::TempDatabaseTest {};

TEST_F(RunStressStrain, LoadingBranchBinnedIntoNominalStressAndStrain) {
  const auto id = record_run(path_, true);
  const auto ss = an::stress_strain_from_run(tocd::db::Reader(path_.string()), id, kRadius, 20);
  EXPECT_DOUBLE_EQ(ss.thickness_mm, kThickness);
  ASSERT_GE(ss.strain.size(), 10u);
  const double area = std::numbers::pi * kRadius * kRadius;
  // Independent bin means: the loading samples d = 1..1200 um fall in 20 strain bins of 0.05.
  std::vector<double> sum(20, 0.0), strain_sum(20, 0.0);
  std::vector<int> n(20, 0);
  for (int i = 1; i <= 1200; ++i) {
    const double strain = i * 1e-3 / kThickness;
    const auto b = std::min<std::size_t>(19, static_cast<std::size_t>(strain * 20));
    sum[b] += load_of(i * 1e-3) / area;
    strain_sum[b] += strain;
    ++n[b];
  }
  std::size_t k = 0;
  for (std::size_t b = 0; b < 20; ++b) {
    if (n[b] == 0) continue;
    ASSERT_LT(k, ss.strain.size());
    EXPECT_NEAR(ss.strain[k], strain_sum[b] / n[b], 1e-12) << "bin " << b;
    EXPECT_NEAR(ss.stress_MPa[k], sum[b] / n[b], 1e-12) << "bin " << b;
    ++k;
  }
  EXPECT_EQ(k, ss.strain.size());
  // Holds below the deepest point, retraction and the approach (d <= 0) are not used.
  EXPECT_EQ(ss.pairs_used, 1200u);
}

TEST_F(RunStressStrain, ErrorsNameWhatIsMissing) {
  const auto id = record_run(path_, false);
  const tocd::db::Reader reader(path_.string());
  try {
    an::stress_strain_from_run(reader, id);
    FAIL() << "no thickness";
  } catch (const tocd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("thickness"), std::string::npos) << e.what();
  }
  EXPECT_THROW(an::stress_strain_from_run(reader, id, -1.0), tocd::ConfigError);
  EXPECT_ANY_THROW(an::stress_strain_from_run(reader, id + 100));
}

}  // namespace

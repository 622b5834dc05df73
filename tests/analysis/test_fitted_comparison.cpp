// analysis::compare_with_fitted_law: a run's stored predictions re-made with another law.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>

#include <gtest/gtest.h>
#include <unistd.h>

#include "predicted_run.hpp"
#include "tocd/analysis/fitted_comparison.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/test/temp_dir.hpp"

namespace an = tocd::analysis;
namespace fs = std::filesystem;

namespace {

class FittedComparison : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<tocd::test::TempDir>("fitted");
    run_ = an::testing::write_predicted_run(*dir_ / "lab.sqlite");
  }
  static void TearDownTestSuite() { dir_.reset(); }

  static std::string fit_file(const std::string& name, const std::string& text) {
    const auto p = *dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }

  static inline std::unique_ptr<tocd::test::TempDir> dir_;  // the suite's, shared by its tests
  static std::int64_t run_;
};
std::int64_t FittedComparison::run_ = 0;

// The stored predictions were made with the published law; the same law from a fit file
// re-makes them: same configs, same seeds, so the same numbers.
TEST_F(FittedComparison, ThePublishedLawReproducesTheStoredPredictions) {
  const tocd::db::Reader reader((*dir_ / "lab.sqlite").string());
  an::FittedComparisonOptions o;
  o.material = fit_file("same.json", an::testing::scaled_fit_json(1.0, {1.0}));
  const auto c = an::compare_with_fitted_law(reader, run_, o);
  ASSERT_EQ(c.steps.size(), 2u);
  EXPECT_FALSE(c.fitted_here);
  for (const auto& s : c.steps) {
    ASSERT_TRUE(std::isfinite(s.T_default)) << s.index;
    EXPECT_DOUBLE_EQ(s.T_fitted, s.T_default) << s.index;
    EXPECT_DOUBLE_EQ(s.T_fitted_se, s.T_default_se) << s.index;
    EXPECT_DOUBLE_EQ(s.band_lo, s.T_fitted);
    EXPECT_DOUBLE_EQ(s.band_hi, s.T_fitted);
  }
  EXPECT_TRUE(std::isnan(c.steps[0].fe_force_default_N)) << "the flat step has no pin force";
  EXPECT_DOUBLE_EQ(c.steps[1].fe_force_fitted_N, c.steps[1].fe_force_default_N);
}

// Every modulus times c scales the stress at a given deformation by c (the strain energy is
// c W), so the FE force at the same pin displacement is c times the default's: a closed-form
// check of the force column. The band spans the confidence laws' T around the fitted T.
TEST_F(FittedComparison, AStifferLawScalesTheForceAndBracketsItsTWithTheBand) {
  const tocd::db::Reader reader((*dir_ / "lab.sqlite").string());
  an::FittedComparisonOptions o;
  o.material = fit_file("stiff.json", an::testing::scaled_fit_json(2.0, {1.6, 2.5}));
  int progress_lines = 0;
  o.progress = [&](const std::string&) { ++progress_lines; };
  const auto c = an::compare_with_fitted_law(reader, run_, o);
  EXPECT_EQ(c.band_laws.size(), 2u);
  EXPECT_EQ(progress_lines, 2) << "one line per re-predicted step";
  const auto& s = c.steps[1];
  // Solver tolerance: the Newton residual of both solves is far below 1e-6 of the force.
  EXPECT_NEAR(s.fe_force_fitted_N / s.fe_force_default_N, 2.0, 1e-6);
  EXPECT_LE(s.band_lo, s.T_fitted);
  EXPECT_GE(s.band_hi, s.T_fitted);
  EXPECT_GT(s.band_hi, s.band_lo) << "laws 1.6x and 2.5x deform the skin differently";
  EXPECT_GT(s.T_fitted_se, 0.0);
  // The flat step does not depend on the law.
  EXPECT_DOUBLE_EQ(c.steps[0].T_fitted, c.steps[0].T_default);
}

TEST_F(FittedComparison, AFileThatIsNoFitIsAClearError) {
  const tocd::db::Reader reader((*dir_ / "lab.sqlite").string());
  an::FittedComparisonOptions o;
  o.material = fit_file("not_a_fit.json", R"({"mu": [1]})");
  try {
    an::compare_with_fitted_law(reader, run_, o);
    FAIL() << "expected ConfigError";
  } catch (const tocd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("not_a_fit.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("tocdlab fit --method fe --json"), std::string::npos) << e.what();
  }
  o.material = (*dir_ / "missing.json").string();
  EXPECT_THROW(an::compare_with_fitted_law(reader, run_, o), tocd::ConfigError);
}

}  // namespace

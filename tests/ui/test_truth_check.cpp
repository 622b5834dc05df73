// The demo's check of an identified sample against the simulated sample's truth
// (ui/cli/truth_check.hpp), on identifications and tables written out by hand: which
// parameters it holds against which truth, when an interval covers it, and the step's z with
// the three errors combined, each expected value worked out here by hand.
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "truth_check.hpp"

namespace an = tocd::analysis;
namespace cli = tocd::cli;
namespace mocks = tocd::mocks;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

an::IdentifiedParameter parameter(const std::string& name, double value, double lo, double hi) {
  an::IdentifiedParameter p;
  p.name = name;
  p.value = value;
  p.lo = lo;
  p.hi = hi;
  p.determined = std::isfinite(lo) && std::isfinite(hi);
  if (!p.determined) p.why_not = "the run carries no information on it";
  return p;
}

// A re-predicted step: its index (0-based), displacement, measured T and the re-predicted T,
// each with its standard error.
an::OpticsIdentification::Step step(int index, double d, double measured, double measured_se,
                                    double predicted, double predicted_se) {
  an::OpticsIdentification::Step s;
  s.step_index = index;
  s.displacement_mm = d;
  s.measured_T = measured;
  s.measured_T_se = measured_se;
  s.predicted_T = predicted;
  s.predicted_T_se = predicted_se;
  return s;
}

// A sample identified with one Prony term, its clearing's time course and optics; the truth it
// is held against is the default sample's (stiffness 1.25, g 0.3, tau 20 s, delayed share 0.3
// over 20 s, cleared 0.6 / 0.6 / 1.1 at log strain 0.5).
an::SampleIdentification identification() {
  an::SampleIdentification id;
  auto& m = id.mechanics.report.parameters;
  m.push_back(parameter("load_offset_N", 0.001, -0.01, 0.01));  // no truth: left out
  m.push_back(parameter("stiffness_scale", 1.24, 1.21, 1.27));  // covers 1.25
  m.push_back(parameter("g1", 0.31, 0.28, 0.34));               // covers 0.3
  m.push_back(parameter("tau1_s", 22.5, 21.0, 24.0));           // misses 20
  an::ClearingIdentification c;
  c.report.parameters.push_back(parameter("delayed_clearing", 0.29, 0.285, 0.295));  // misses 0.3
  c.report.parameters.push_back(parameter("delayed_clearing_time_s", 19.0, kInf, kInf));
  c.report.parameters.push_back(parameter("T_eq_at_0.250_mm", 0.2, 0.19, 0.21));  // no truth
  id.clearing = c;
  an::OpticsIdentification o;
  o.report.parameters.push_back(parameter("cleared_mu_a_fraction", 0.5, 0.1, 1.0));
  o.report.parameters.back().determined = false;  // an interval as wide as its range
  o.report.parameters.push_back(parameter("full_clearing_strain", 0.52, 0.45, 0.59));  // covers 0.5
  o.steps.push_back(step(1, 0.25, 0.2, 0.0004, 0.205, 0.0012));
  o.steps.push_back(step(2, 0.5, 0.3, 0.0, 0.3, 0.0));
  id.optics = o;
  return id;
}

// Relative errors 1 % at contact, 2 % at 0.5 mm, 4 % at 1 mm.
mocks::SimTissueTable table() {
  mocks::SimTissueTable t;
  t.displacement_mm = {0.0, 0.5, 1.0};
  t.transmission = {0.1, 0.3, 0.5};
  t.transmission_stderr = {0.001, 0.006, 0.02};
  return t;
}

const cli::TruthCheck::Parameter* find(const cli::TruthCheck& c, const std::string& name) {
  for (const auto& p : c.parameters)
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace

TEST(TruthCheck, HoldsEachIdentifiedParameterAgainstItsOwnTruth) {
  const auto c = cli::check_against_truth(identification(), mocks::SampleTruth{}, table());
  // Truth order (stiffness, relaxation, optics, delayed clearing); those the identification
  // has, under its own names; the load offset and the equilibrium T have no truth.
  ASSERT_EQ(c.parameters.size(), 7u);
  const char* names[] = {"stiffness_scale",
                         "g1",
                         "tau1_s",
                         "cleared_mu_a_fraction",
                         "full_clearing_strain",
                         "delayed_clearing",
                         "delayed_clearing_time_s"};
  for (std::size_t k = 0; k < 7; ++k) EXPECT_EQ(c.parameters[k].name, names[k]);
  EXPECT_DOUBLE_EQ(find(c, "g1")->truth, 0.3);
  EXPECT_DOUBLE_EQ(find(c, "tau1_s")->truth, 20.0);
  EXPECT_DOUBLE_EQ(find(c, "full_clearing_strain")->truth, 0.5);
  EXPECT_TRUE(find(c, "stiffness_scale")->covered);
  EXPECT_TRUE(find(c, "g1")->covered);
  EXPECT_FALSE(find(c, "tau1_s")->covered);
  EXPECT_FALSE(find(c, "delayed_clearing")->covered);
  EXPECT_TRUE(find(c, "full_clearing_strain")->covered);
  EXPECT_FALSE(find(c, "delayed_clearing_time_s")->determined);
  EXPECT_FALSE(find(c, "delayed_clearing_time_s")->covered) << "no interval covers nothing";
  EXPECT_FALSE(find(c, "cleared_mu_a_fraction")->determined);
  // Determined: stiffness, g1, tau1, the strain and the delayed share; covering: three of them.
  EXPECT_EQ(c.determined(), 5);
  EXPECT_EQ(c.covered(), 3);
}

TEST(TruthCheck, CombinesTheWindowTheSampleAndTheMonteCarloErrors) {
  const auto c = cli::check_against_truth(identification(), mocks::SampleTruth{}, table());
  ASSERT_EQ(c.steps.size(), 2u);
  const auto& s = c.steps[0];
  EXPECT_EQ(s.step, 2);
  // The sample's relative error halfway between 1 % (contact) and 2 % (0.5 mm): 1.5 % of the
  // measured 0.2 is 0.003. Combined: sqrt(0.0004^2 + 0.003^2 + 0.0012^2) = sqrt(1.06e-5).
  EXPECT_NEAR(s.sample_se, 0.003, 1e-15);
  EXPECT_NEAR(s.combined_se, std::sqrt(1.06e-5), 1e-15);
  EXPECT_NEAR(s.z, 0.005 / std::sqrt(1.06e-5), 1e-12);  // 1.536
  // At a table point its own error: 2 % of 0.3.
  EXPECT_NEAR(c.steps[1].sample_se, 0.006, 1e-15);
  EXPECT_EQ(c.steps[1].z, 0.0);
  EXPECT_EQ(c.steps_within(1.0), 1);
  EXPECT_EQ(c.steps_within(2.0), 2);
}

TEST(TruthCheck, BeyondTheTableTheNearestEndsErrorHolds) {
  auto id = identification();
  id.optics->steps[0].displacement_mm = 1.5;  // beyond the table's 1 mm: its 4 %
  const auto c = cli::check_against_truth(id, mocks::SampleTruth{}, table());
  EXPECT_NEAR(c.steps[0].sample_se, 0.04 * 0.2, 1e-15);
}

TEST(TruthCheck, MoreThanOnePronyTermHasNoTruthForG1AndTau1) {
  auto id = identification();
  id.mechanics.report.parameters.push_back(parameter("g2", 0.1, 0.05, 0.15));
  id.mechanics.report.parameters.push_back(parameter("tau2_s", 200, 100, 300));
  const auto c = cli::check_against_truth(id, mocks::SampleTruth{}, table());
  EXPECT_EQ(find(c, "g1"), nullptr);
  EXPECT_EQ(find(c, "tau1_s"), nullptr);
  EXPECT_NE(find(c, "stiffness_scale"), nullptr);
}

TEST(TruthCheck, WithoutOpticsThereAreNoSteps) {
  auto id = identification();
  id.optics.reset();
  const auto c = cli::check_against_truth(id, mocks::SampleTruth{}, table());
  EXPECT_TRUE(c.steps.empty());
  EXPECT_EQ(find(c, "full_clearing_strain"), nullptr);
  std::ostringstream text;
  cli::print_truth_check(text, c);
  EXPECT_EQ(text.str().find("combined_se"), std::string::npos) << text.str();
}

TEST(TruthCheck, TextAndJsonSayTheSame) {
  const auto c = cli::check_against_truth(identification(), mocks::SampleTruth{}, table());
  std::ostringstream text;
  cli::print_truth_check(text, c);
  EXPECT_NE(text.str().find("3 of 5 determined intervals cover the truth"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("1 of 2 steps within 1, 2 within 2"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("NO"), std::string::npos) << "a miss is spelled out";
  const auto j = cli::to_json(c);
  EXPECT_EQ(j["determined"], 5);
  EXPECT_EQ(j["determined_covering_truth"], 3);
  EXPECT_EQ(j["steps_within_1_se"], 1);
  EXPECT_EQ(j["steps_within_2_se"], 2);
  EXPECT_TRUE(j["parameters"][3]["covers_truth"].is_null()) << "not determined: no claim";
  EXPECT_TRUE(j["parameters"][6]["interval"][0].is_null()) << "no interval: null, not inf";
  EXPECT_NEAR(j["steps"][0]["z"].get<double>(), c.steps[0].z, 0.0);
}

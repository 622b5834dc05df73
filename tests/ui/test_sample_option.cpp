// The truth options as a command parses them: each field set by its option, --truth-seed
// drawing the rest, the demo's --delayed-clearing as an alias, and what the analytic sample
// refuses or takes.
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>

#include "sample_option.hpp"

namespace cli = tocd::cli;
namespace mocks = tocd::mocks;

namespace {

cli::SampleChoice parse(std::vector<std::string> args, bool alias = false) {
  CLI::App app;
  cli::SampleChoice choice;
  if (alias) {
    cli::add_truth_options(app, choice, true);
  } else {
    cli::add_sample_options(app, choice);
  }
  std::reverse(args.begin(), args.end());  // CLI11 takes them last first
  app.parse(args);
  return choice;
}

}  // namespace

TEST(TruthOptions, NoneGivenIsTheDefaultSample) {
  const cli::SampleChoice c = parse({});
  EXPECT_FALSE(cli::truth_given(c));
  EXPECT_EQ(cli::first_truth_option(c), nullptr);
  EXPECT_EQ(cli::sample_truth(c), mocks::SampleTruth{});
  const mocks::SimulatedLabOptions o = cli::simulated_lab_options(c);
  EXPECT_EQ(o.delayed_clearing, mocks::kDefaultDelayedClearing);
}

TEST(TruthOptions, EachOptionSetsItsField) {
  for (const auto& f : mocks::kSampleTruthFields) {
    const mocks::TruthRange r = mocks::SampleTruthRanges{}.*f.range;
    const double v = 0.5 * (r.lo + r.hi) + 0.001;
    const cli::SampleChoice c = parse({f.option, std::to_string(v)});
    EXPECT_TRUE(cli::truth_given(c));
    mocks::SampleTruth want;
    want.*f.value = std::stod(std::to_string(v));
    EXPECT_EQ(cli::sample_truth(c), want) << f.option;
  }
}

TEST(TruthOptions, SeedDrawsTheFieldsNotGiven) {
  const cli::SampleChoice c = parse({"--truth-seed", "42", "--truth-relaxation-time", "9"});
  EXPECT_STREQ(cli::first_truth_option(c), "--truth-seed");
  EXPECT_STREQ(cli::first_truth_option(parse({"--truth-delayed-clearing-time", "9"})),
               "--truth-delayed-clearing-time");
  mocks::SampleTruth want = mocks::draw_sample_truth(42);
  want.relaxation_time_s = 9;
  EXPECT_EQ(cli::sample_truth(c), want);
}

TEST(TruthOptions, OutOfRangeIsAUsageErrorNamingTheOption) {
  try {
    parse({"--truth-full-clearing-strain", "3"});
    ADD_FAILURE() << "accepted";
  } catch (const CLI::ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("--truth-full-clearing-strain"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse({"--truth-delayed-clearing", "nan"}), CLI::ParseError);
  EXPECT_THROW(parse({"--truth-seed", "-1"}), CLI::ParseError);
}

TEST(TruthOptions, DemoKeepsDelayedClearingAsAnAlias) {
  const cli::SampleChoice c = parse({"--delayed-clearing", "0.1"}, true);
  EXPECT_EQ(cli::sample_truth(c).delayed_clearing, 0.1);
  EXPECT_EQ(cli::simulated_lab_options(c).delayed_clearing, 0.1);
  EXPECT_THROW(parse({"--delayed-clearing", "0.1"}), CLI::ParseError);  // demo only
}

TEST(TruthOptions, AnalyticSampleTakesTheLabsTimeBehaviourOnly) {
  // Relaxation and delayed clearing apply to both samples; the analytic one clears at once
  // unless asked.
  cli::SampleChoice c = parse({"--sample", "analytic", "--truth-relaxation-fraction", "0.2"});
  mocks::SimulatedLabOptions o = cli::simulated_lab_options(c);
  EXPECT_EQ(o.relaxation_fraction, 0.2);
  EXPECT_EQ(o.delayed_clearing, 0.0);
  c = parse(
      {"--sample", "analytic", "--truth-delayed-clearing", "0.4", "--truth-delayed-clearing-time", "9"});
  o = cli::simulated_lab_options(c);
  EXPECT_EQ(o.delayed_clearing, 0.4);
  EXPECT_EQ(o.delayed_clearing_time_s, 9);
  const std::vector<std::pair<std::string, std::string>> refused_options = {
      {"--truth-stiffness-scale", "1.5"},
      {"--truth-cleared-mu-a", "0.5"},
      {"--truth-cleared-mu-s", "0.5"},
      {"--truth-cleared-n", "1.05"},
      {"--truth-full-clearing-strain", "0.4"}};
  for (const auto& [refused, value] : refused_options) {
    c = parse({"--sample", "analytic", refused, value});
    try {
      cli::sample_truth(c);
      ADD_FAILURE() << refused << " accepted with --sample analytic";
    } catch (const CLI::ValidationError& e) {
      EXPECT_NE(std::string(e.what()).find(refused), std::string::npos) << e.what();
    }
  }
  c = parse({"--sample", "analytic", "--truth-seed", "1"});
  EXPECT_THROW(cli::sample_truth(c), CLI::ValidationError);
}

// The progress display and the naming table on their own (no executable): what a bar line
// says, when it is drawn, and how simulator JSON and CSV are brought to docs/cli.md's names.
#include <chrono>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "output_naming.hpp"
#include "progress.hpp"

namespace cli = tocd::cli;

TEST(ProgressFormat, BarShowsFractionRateAndEta) {
  // 250 of 1000 photons in 5 s: 50 photons/s, 750 left -> 15 s.
  const std::string line = cli::format_progress("mc", 250, 1000, "photons", 5.0, 20);
  EXPECT_NE(line.find("[#####...............]"), std::string::npos) << line;
  EXPECT_NE(line.find(" 25%"), std::string::npos) << line;
  EXPECT_NE(line.find("250/1000 photons"), std::string::npos) << line;
  EXPECT_NE(line.find("50/s"), std::string::npos) << line;
  EXPECT_NE(line.find("ETA 0:15"), std::string::npos) << line;
}

TEST(ProgressFormat, UnknownTotalShowsElapsedOnly) {
  const std::string line = cli::format_progress("fe", 0, 0, "", 65.0);
  EXPECT_EQ(line.find('['), std::string::npos) << line;
  EXPECT_NE(line.find("elapsed 1:05"), std::string::npos) << line;
}

TEST(ProgressFormat, ClockText) {
  EXPECT_EQ(cli::clock_text(3723.0), "1:02:03");
  EXPECT_EQ(cli::clock_text(-1.0), "-");
}

TEST(ProgressBar, BarModeRedrawsInPlaceAndEndsTheLine) {
  std::ostringstream out;
  {
    cli::ProgressBar bar(out, cli::ProgressMode::bar, "job", 10, "items");
    bar.update(3);  // within 0.1 s of the start: not drawn
    bar.finish();
  }
  const std::string s = out.str();
  EXPECT_EQ(s.rfind("\r\33[K", 0), 0u) << s;
  EXPECT_NE(s.find("3/10 items"), std::string::npos) << s;
  EXPECT_EQ(s.back(), '\n');
  EXPECT_EQ(s.find("3/10", s.find("3/10") + 1), std::string::npos) << "drawn twice: " << s;
}

TEST(ProgressBar, LineModeWritesPlainLinesAtItsInterval) {
  std::ostringstream out;
  cli::ProgressBar bar(out, cli::ProgressMode::lines, "job", 4, "items", std::chrono::milliseconds(0));
  bar.update(1);
  bar.update(2);
  bar.note("a row");
  bar.finish();
  const std::string s = out.str();
  EXPECT_EQ(s.find('\r'), std::string::npos) << s;
  EXPECT_NE(s.find("1/4 items"), std::string::npos) << s;
  EXPECT_NE(s.find("2/4 items"), std::string::npos) << s;
  EXPECT_NE(s.find("a row\n"), std::string::npos) << s;
}

TEST(ProgressBar, LineModeSaysNothingForAShortJob) {
  std::ostringstream out;
  {
    cli::ProgressBar bar(out, cli::ProgressMode::lines, "job", 4, "items");  // 5 s interval
    bar.update(4);
  }
  EXPECT_EQ(out.str(), "");
}

TEST(ProgressBar, OffWritesNothing) {
  std::ostringstream out;
  {
    cli::ProgressBar bar(out, cli::ProgressMode::off, "job", 4, "items", std::chrono::milliseconds(0));
    bar.update(2);
    bar.note("row");
  }
  EXPECT_EQ(out.str(), "");
}

TEST(NamingTable, EstimatesStderrKeysAndSteps) {
  const auto in = nlohmann::json::parse(R"({
    "transmittance": {"mean": 0.5, "se": 0.01},
    "T_stderr": 0.02,
    "nested": {"absorbed": {"mean": 0.1, "se": 0.001}},
    "steps": [{"index": 0, "predicted_T_stderr": 0.3}, {"index": 1}],
    "other": {"mean": 1, "se": 2, "n": 3}
  })");
  const auto j = cli::to_naming_table(in);
  EXPECT_EQ(j["transmittance"], 0.5);
  EXPECT_EQ(j["transmittance_se"], 0.01);
  EXPECT_EQ(j["T_se"], 0.02);
  EXPECT_FALSE(j.contains("T_stderr"));
  EXPECT_EQ(j["nested"]["absorbed_se"], 0.001);
  EXPECT_EQ(j["steps"][0]["step"], 1);
  EXPECT_EQ(j["steps"][1]["step"], 2);
  EXPECT_FALSE(j["steps"][0].contains("index"));
  EXPECT_EQ(j["steps"][0]["predicted_T_se"], 0.3);
  EXPECT_TRUE(j["other"].is_object()) << "only a {mean, se} pair is an estimate";
}

TEST(NamingTable, CsvHeaderAndLineEndings) {
  const std::string csv = cli::to_naming_table_csv("step,T,T_stderr\r\n1,0.5,0.01\r\n");
  EXPECT_EQ(csv, "step,T,T_se\n1,0.5,0.01\n");
}

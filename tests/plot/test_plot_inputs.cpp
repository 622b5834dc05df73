// Readers of tocdlab plot's inputs: slice CSVs and a study's JSON.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "tocd/core/error.hpp"
#include "tocd/plot/inputs.hpp"
#include "tocd/test/error_of.hpp"

using namespace tocd::plot;

namespace {

std::string message_of(const std::function<void()>& f) {
  return tocd::test::error_of<tocd::ConfigError>(f);
}

}  // namespace

TEST(PlotSliceCsv, HorizontalSliceBecomesAnXYGridWithCellsCentredOnPoints) {
  const std::string csv =
      "x_mm,y_mm,z_mm,region,fluence,fluence_se\n"
      "-0.5,-0.5,1.2,1,0.1,0.01\n0.5,-0.5,1.2,1,0.2,0.01\n1.5,-0.5,1.2,2,0.3,0.01\n"
      "-0.5,0.5,1.2,0,,\n0.5,0.5,1.2,2,0.5,0.01\n1.5,0.5,1.2,2,0.6,0.01\n";
  const Slice s = parse_slice_csv(csv, "h.csv");
  EXPECT_EQ(s.nx, 3);
  EXPECT_EQ(s.ny, 2);
  EXPECT_EQ(s.x_label, "x (mm)");
  EXPECT_EQ(s.y_label, "y (mm)");
  EXPECT_EQ(s.title, "z = 1.2 mm") << "the panel names its plane";
  EXPECT_DOUBLE_EQ(s.x_min, -1.0);
  EXPECT_DOUBLE_EQ(s.x_max, 2.0);
  EXPECT_DOUBLE_EQ(s.y_min, -1.0);
  EXPECT_DOUBLE_EQ(s.y_max, 1.0);
  EXPECT_DOUBLE_EQ(s.fluence[2], 0.3);
  EXPECT_TRUE(std::isnan(s.fluence[3]));
  EXPECT_EQ(s.region[3], 0);
  EXPECT_EQ(s.region[5], 2);
}

TEST(PlotSliceCsv, BadInputNamesFileAndLine) {
  EXPECT_NE(message_of([] { parse_slice_csv("a,b\n", "s.csv"); }).find("s.csv:1"), std::string::npos);
  const std::string bad = "x_mm,y_mm,z_mm,region,fluence,fluence_se\n0,0,0,1,0.1,0\n1,0,x,1,0.1,0\n";
  const auto m = message_of([&] { parse_slice_csv(bad, "s.csv"); });
  EXPECT_NE(m.find("s.csv:3"), std::string::npos) << m;
  EXPECT_NE(m.find("z_mm"), std::string::npos) << m;
  const std::string holes =
      "x_mm,y_mm,z_mm,region,fluence,fluence_se\n0,0,0,1,1,0\n1,0,0,1,1,0\n0,0,1,1,1,0\n";
  EXPECT_NE(message_of([&] { parse_slice_csv(holes, "s.csv"); }).find("grid"), std::string::npos);
}

TEST(PlotStudyJson, OneBarPerSimulationWithTheColumnAndItsError) {
  const std::string j = R"({"kind": "tocdlab.study", "simulations": [
    {"sim": 0, "displacement_mm": 0, "optics": "glass", "T": 0.9, "T_se": 0.01, "T_rel_b": null},
    {"sim": 1, "displacement_mm": 0.5, "optics": "native", "T": 0.3, "T_se": 0.02, "T_rel_b": 1.0, "T_rel_b_se": 0.05},
    {"sim": 2, "displacement_mm": 1.0, "optics": "native", "T": 0.4, "T_se": 0.03, "T_rel_b": 1.3, "T_rel_b_se": 0.06}]})";
  const BarFigure t = parse_study_bars(j, "T", "s.json");
  ASSERT_EQ(t.values.size(), 3u);
  EXPECT_DOUBLE_EQ(t.values[2], 0.4);
  EXPECT_DOUBLE_EQ(t.errors[1], 0.02);
  const BarFigure rel = parse_study_bars(j, "T_rel_b", "s.json");
  ASSERT_EQ(rel.values.size(), 2u);  // the glass-only row has no relative value
  EXPECT_DOUBLE_EQ(rel.values[1], 1.3);
  EXPECT_DOUBLE_EQ(rel.errors[0], 0.05);
  EXPECT_NE(rel.labels[0].find("0.5\u00a0mm"), std::string::npos) << rel.labels[0];
}

TEST(PlotStudyJson, WrongFilesAndColumnsAreNamed) {
  EXPECT_NE(message_of([] { parse_study_bars("{", "T", "s.json"); }).find("s.json: not valid JSON"),
            std::string::npos);
  EXPECT_NE(message_of([] { parse_study_bars(R"({"kind": "other"})", "T", "s.json"); }).find("not a study"),
            std::string::npos);
  const std::string j = R"({"kind": "tocdlab.study", "simulations": [{"sim": 4, "T": 0.9}]})";
  const auto m = message_of([&] { parse_study_bars(j, "Tx", "s.json"); });
  EXPECT_NE(m.find("simulation 4 has no column 'Tx'"), std::string::npos) << m;
}

TEST(PlotSensitivityJson, OneBarPerTornadoRowInItsOrder) {
  const std::string j = R"({"base": {"T": 0.3179}, "rows": [],
    "tornado": [{"factor": "compressed threshold", "label": "-0.6 log strain", "dT": -0.0107, "dT_se": 0.00045},
                {"factor": "slide index", "label": "1.52", "dT": -0.0021, "dT_se": 0.0001}]})";
  const auto f = parse_sensitivity_tornado(j, "s.json");
  ASSERT_EQ(f.values.size(), 2u);
  EXPECT_EQ(f.labels[0], "compressed threshold: -0.6 log strain");
  EXPECT_DOUBLE_EQ(f.values[1], -0.0021);
  EXPECT_DOUBLE_EQ(f.errors[0], 0.00045);
  EXPECT_NE(f.title.find("0.3179"), std::string::npos);
  const auto m = message_of([&] { parse_sensitivity_tornado(R"({"simulations": []})", "study.json"); });
  EXPECT_NE(m.find("study.json"), std::string::npos) << m;
  EXPECT_NE(m.find("study sensitivity --json"), std::string::npos) << m;
}

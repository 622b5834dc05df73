// What each figure says and where it puts it: labels, titles, bar values, error bar ends and
// the colour scale, computed from the inputs (the layouts the painters draw), plus pixel
// checks where the geometry itself is the point.
#include <QColor>
#include <QImage>
#include <QString>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "colour_match.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/figures.hpp"
#include "tocd/plot/inputs.hpp"
#include "tocd/test/temp_dir.hpp"

namespace fs = std::filesystem;
using namespace tocd::plot;
using tocd::plot::testing::same_colour;

namespace {

std::string hex_of(Rgb c) {
  return QColor(c.r, c.g, c.b).name().toStdString();
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += (out.empty() ? "" : " ") + l;
  return out;
}

bool overlap(const PixelRect& a, const PixelRect& b) {
  return a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
}

bool inside(const PixelRect& r, FigureSize size) {
  return r.x >= 0 && r.y >= 0 && r.x + r.width <= size.width && r.y + r.height <= size.height;
}

// The published study's twelve simulations as `study paper --json` describes them: sim 0 the
// glass-only baseline, 1-3 native skin at 0, 0.625 and 1.5 mm, 4-11 the optics changes at
// 1.5 mm. T_rel_b (T / T3) is filled for every row, as the JSON is once sim 3 has run.
std::string paper_study_json() {
  const char* optics[] = {"glass only", "native",   "native", "native", "mu_a 80%",     "mu_a 60%",
                          "mu_s 80%",   "mu_s 60%", "n 105%", "n 110%", "a80 s80 n105", "a60 s60 n110"};
  const double d[] = {0, 0, 0.625, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5};
  const double T[] = {0.40, 0.049, 0.105, 0.207, 0.216, 0.227, 0.237, 0.279, 0.220, 0.221, 0.263, 0.320};
  std::string sims;
  for (int k = 0; k < 12; ++k) {
    const double h = k == 0 ? 0.0 : 2.5;
    sims += fmt::format(
        R"({}{{"sim": {}, "displacement_mm": {}, "thickness_mm": {}, "strain": {}, "optics": "{}",
            "config": {{"baseline": {}, "displacement_mm": {}, "thickness_mm": 2.5}},
            "T": {}, "T_se": 0.001, "T_rel_a": {}, "T_rel_a_se": 0.003, "T_rel_b": {}, "T_rel_b_se": {}}})",
        k == 0 ? "" : ",", k, d[k], h, h > 0 ? d[k] / h : 0.0, optics[k], k == 0 ? "true" : "false", d[k],
        T[k], T[k] / T[0], T[k] / T[3], k == 3 ? 0.0 : 0.004);
  }
  return R"({"kind": "tocdlab.study", "reference_a": 0, "reference_b": 3, "simulations": [)" + sims + "]}";
}

}  // namespace

// Sim 1 is flat native skin and is labelled so (it used to read "1: glass": its displacement
// of 0 was taken for the baseline); every label names the optics and the state.
TEST(PlotStudyBars, EachSimulationIsLabelledByWhatTheStudySaysItIs) {
  const BarFigure t = parse_study_bars(paper_study_json(), "T", "paper.json");
  ASSERT_EQ(t.labels.size(), 12u);
  EXPECT_TRUE(contains(t.labels[0], "0: glass only")) << t.labels[0];
  EXPECT_TRUE(contains(t.labels[1], "1: native")) << t.labels[1];
  EXPECT_TRUE(contains(t.labels[1], "flat, 0\u00a0mm")) << t.labels[1];
  EXPECT_FALSE(contains(t.labels[1], "glass")) << t.labels[1];
  EXPECT_TRUE(contains(t.labels[2], "0.625\u00a0mm, 25\u00a0%")) << t.labels[2];
  EXPECT_TRUE(contains(t.labels[4], "mu_a 80%")) << t.labels[4];
  EXPECT_TRUE(contains(t.labels[11], "a60 s60 n110")) << t.labels[11];
  EXPECT_TRUE(contains(t.labels[11], "1.5\u00a0mm, 60\u00a0%")) << t.labels[11];
  // Axis labels are words with their unit, not the JSON's keys.
  EXPECT_EQ(t.y_label, "transmission T (fraction of the light)");
  EXPECT_FALSE(t.x_label.empty());
}

// The study's table prints "-" for T/T3 before sim 3 has run (sims 0-2) and the published
// table leaves them out; the JSON fills them in afterwards. The bars follow the table: the
// glass-only baseline is not drawn at T0/T3 (about 2), nor are sims 1 and 2.
TEST(PlotStudyBars, RelativeColumnDrawsTheReferenceAndTheSimulationsAfterIt) {
  const BarFigure rel = parse_study_bars(paper_study_json(), "T_rel_b", "paper.json");
  ASSERT_EQ(rel.values.size(), 9u);
  EXPECT_TRUE(contains(rel.labels.front(), "3: native")) << rel.labels.front();
  EXPECT_DOUBLE_EQ(rel.values.front(), 1.0);
  EXPECT_NEAR(rel.values.back(), 0.320 / 0.207, 1e-12);
  EXPECT_DOUBLE_EQ(rel.errors[1], 0.004);
  for (double v : rel.values) EXPECT_LT(v, 1.9) << "a row before the reference was drawn";
  EXPECT_FALSE(contains(rel.y_label, "T_rel_b")) << rel.y_label;
  EXPECT_TRUE(contains(rel.y_label, "relative to sim 3")) << rel.y_label;
  EXPECT_TRUE(contains(rel.title, "T / T3 (sim 3: native, 1.5 mm, 60 %)")) << rel.title;
  // T/T0: the baseline is its reference and the first row: every simulation has a bar.
  EXPECT_EQ(parse_study_bars(paper_study_json(), "T_rel_a", "paper.json").values.size(), 12u);
}

// The twelve labels of the published study on the default 900 x 600 figure: wrapped to their
// slots, none running into another or out of the figure; on a narrow figure they turn upright.
TEST(PlotStudyBars, LabelsNeitherOverlapNorLeaveTheFigure) {
  const BarFigure f = parse_study_bars(paper_study_json(), "T", "paper.json");
  for (const FigureSize size : {FigureSize{900, 600}, FigureSize{500, 400}}) {
    const BarLayout l = bar_layout(f, size);
    ASSERT_EQ(l.label_boxes.size(), 12u);
    const double slot = l.area.width / 12;
    for (std::size_t k = 0; k < 12; ++k) {
      EXPECT_TRUE(inside(l.label_boxes[k], size)) << size.width << ": label " << k;
      EXPECT_LE(l.label_boxes[k].width, slot) << size.width << ": label " << k;
      EXPECT_GE(l.label_boxes[k].y, l.area.y + l.area.height) << "labels hang below the axis";
      if (k > 0) {
        EXPECT_FALSE(overlap(l.label_boxes[k - 1], l.label_boxes[k])) << size.width << ": " << k;
      }
      // No text is lost: the lines hold every word of the label.
      if (!l.labels_rotated) {
        std::string words = f.labels[k], lines = joined(l.label_lines[k]);
        std::replace(words.begin(), words.end(), '\n', ' ');
        for (auto at = words.find("\u00a0"); at != std::string::npos; at = words.find("\u00a0"))
          words.replace(at, 2, " ");
        for (auto at = lines.find("\u00a0"); at != std::string::npos; at = lines.find("\u00a0"))
          lines.replace(at, 2, " ");
        EXPECT_EQ(lines, words);
      }
    }
    EXPECT_EQ(l.labels_rotated, size.width == 500) << "upright at 900 px, turned at 500 px";
  }
  // Bars end at their values (sim 0: 0.40, sim 3: 0.207), error bars at +-1 standard error.
  const BarLayout l = bar_layout(f, {900, 600});
  EXPECT_NEAR(l.bars[0].height / l.bars[3].height, 0.40 / 0.207, 0.01);
  const double per_unit = l.area.height / (l.y_hi - l.y_lo);
  EXPECT_NEAR(l.error_low_y[0] - l.error_high_y[0], 2 * 0.001 * per_unit, 1e-9);
}

namespace {

CompareFigure three_steps() {
  CompareFigure f;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  f.steps = {
      {0, 0.5, 0.30, 0.33, 0.05, 0.03}, {1, 1.0, 0.40, 0.46, 0.06, 0.04}, {2, 1.5, nan, 0.55, 0.07, nan}};
  return f;
}

// The dark column of an error bar just above a marker, and the marker's middle column: the
// first and last columns of `colour` on the marker's middle row.
void marker_and_bar_columns(const QImage& img, const CompareMarker& m, Rgb colour, double& marker_mid,
                            int& bar_column) {
  const int row = static_cast<int>(std::floor(m.y));
  int first = -1, last = -1;
  for (int x = static_cast<int>(m.x) - 12; x <= static_cast<int>(m.x) + 12; ++x)
    if (same_colour(img.pixelColor(x, row), colour, 10)) {
      if (first < 0) first = x;
      last = x;
    }
  marker_mid = 0.5 * (first + last);
  // Halfway between the marker's top and the bar's upper cap: only the bar is there.
  const int y = static_cast<int>(std::floor(0.5 * (m.y - kCompareMarkerRadius + m.error_high_y)));
  bar_column = -1;
  int darkest = 255 * 3;
  for (int x = static_cast<int>(m.x) - 12; x <= static_cast<int>(m.x) + 12; ++x) {
    const QColor c = img.pixelColor(x, y);
    if (c.red() + c.green() + c.blue() < darkest) darkest = c.red() + c.green() + c.blue(), bar_column = x;
  }
}

}  // namespace

// Every marker carries its error bar at its own centre, measured T included, and the legend
// says what the bars are.
TEST(PlotCompare, ErrorBarsAreCentredOnTheirMarkersForMeasuredAndPredicted) {
  const FigureSize size{900, 600};
  const CompareFigure f = three_steps();
  const CompareLayout l = compare_layout(f, size);
  ASSERT_EQ(l.measured.size(), 2u);
  ASSERT_EQ(l.predicted.size(), 3u);
  const double per_unit = l.area.height / (l.y_hi - l.y_lo);
  for (const auto& m : l.measured) {
    const auto& s = f.steps[static_cast<std::size_t>(m.step)];
    ASSERT_TRUE(std::isfinite(m.error_low_y)) << "measured step " << m.step << " has no error bar";
    EXPECT_NEAR(m.error_low_y - m.error_high_y, 2 * s.measured_T_se * per_unit, 1e-9);
    EXPECT_NEAR(0.5 * (m.error_low_y + m.error_high_y), m.y, 1e-9) << "bar not centred on the marker";
  }
  for (const auto& m : l.predicted) {
    const auto& s = f.steps[static_cast<std::size_t>(m.step)];
    EXPECT_NEAR(m.error_low_y - m.error_high_y, 2 * s.predicted_T_se * per_unit, 1e-9);
    EXPECT_NEAR(0.5 * (m.error_low_y + m.error_high_y), m.y, 1e-9);
  }
  EXPECT_TRUE(contains(l.legend[0], "\u00b11 standard error")) << l.legend[0];
  EXPECT_TRUE(contains(l.legend[1], "\u00b11 Monte Carlo standard error")) << l.legend[1];
  // On the picture: the bar's dark column is the marker's middle column.
  const fs::path png = tocd::test::process_temp_path("compare.png");
  write_figure(f, png, size);
  const QImage img(QString::fromStdString(png.string()));
  ASSERT_FALSE(img.isNull());
  for (const auto& [markers, colour] :
       {std::pair{&l.measured, kMeasuredColour}, std::pair{&l.predicted, kPredictedColour}})
    for (const auto& m : *markers) {
      double mid = 0;
      int bar = 0;
      marker_and_bar_columns(img, m, colour, mid, bar);
      EXPECT_NEAR(mid, bar, 0.5) << "step " << m.step << ": marker middle " << mid << ", bar column " << bar;
    }
  // Without a measured standard error there is no bar, and the legend does not promise one.
  CompareFigure bare = f;
  for (auto& s : bare.steps) s.measured_T_se = std::numeric_limits<double>::quiet_NaN();
  const CompareLayout b = compare_layout(bare, size);
  EXPECT_FALSE(std::isfinite(b.measured[0].error_low_y));
  EXPECT_EQ(b.legend[0], "measured");
}

// The tornado's title names the quantity and the step; its key says what pale and dark mean.
TEST(PlotTornado, TitleNamesTheStepAndTheKeyExplainsPaleAndDarkBars) {
  const std::string j = R"({"base": {"T": 0.3179, "T_se": 0.0004,
      "config": {"baseline": false, "displacement_mm": 1.5, "thickness_mm": 2.5}},
    "tornado": [{"factor": "compressed threshold", "label": "-0.6 log strain", "dT": -0.0107, "dT_se": 0.00045},
                {"factor": "slide index", "label": "1.52", "dT": 0.0004, "dT_se": 0.0003}]})";
  const TornadoFigure f = parse_sensitivity_tornado(j, "s.json");
  EXPECT_TRUE(contains(f.title, "transmission")) << f.title;
  EXPECT_TRUE(contains(f.title, "1.5 mm step")) << f.title;
  EXPECT_TRUE(contains(f.title, "2.5 mm skin, 60 % strain")) << f.title;
  EXPECT_TRUE(contains(f.title, "0.3179")) << f.title;
  const FigureSize size{800, 400};
  const TornadoLayout l = tornado_layout(f, size);
  ASSERT_EQ(l.resolved.size(), 2u);
  EXPECT_TRUE(l.resolved[0]);
  EXPECT_FALSE(l.resolved[1]);
  ASSERT_EQ(l.key.size(), 2u);
  EXPECT_TRUE(contains(l.key[0], "> 2 s.e.")) << l.key[0];
  EXPECT_TRUE(contains(l.key[1], "\u2264 2 s.e.")) << l.key[1];
  for (const auto& box : l.key_boxes) {
    EXPECT_TRUE(inside(box, size));
    EXPECT_GT(box.y, l.area.y + l.area.height + 30) << "the key sits below the x axis' label";
  }
  EXPECT_FALSE(overlap(l.key_boxes[0], l.key_boxes[1]));
  // The picture's key shows both colours, in their boxes.
  const fs::path png = tocd::test::process_temp_path("tornado.png");
  write_figure(f, png, size);
  const QImage img(QString::fromStdString(png.string()));
  const Rgb colours[2] = {kMeasuredColour, kUnresolvedColour};
  for (int k = 0; k < 2; ++k) {
    const PixelRect& b = l.key_boxes[static_cast<std::size_t>(k)];
    EXPECT_TRUE(same_colour(img.pixelColor(static_cast<int>(b.x + 7), static_cast<int>(b.y + b.height / 2)),
                            colours[k]))
        << "key entry " << k;
  }
}

namespace {

// A 100 x 40 x-z slice of fluence falling from 1e-1 (left) to 1e-5 (right) with, at the pin
// tip, three cells of 100 (tiny tets that caught one photon's long track), four cells no photon
// reached (fluence 0, inside the mesh) and a 2 x 2 corner outside the mesh.
Slice noisy_slice() {
  std::string csv = "x_mm,y_mm,z_mm,region,fluence,fluence_se\n";
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 100; ++i) {
      const double x = 0.05 + 0.1 * i, z = 0.05 + 0.1 * j;
      std::string fl = fmt::format("{:.6g}", std::pow(10.0, -1.0 - 4.0 * i / 99.0));
      int region = 4;
      if (j == 20 && i >= 50 && i < 53) fl = "100";
      if (j == 10 && i >= 30 && i < 34) fl = "0";
      if (i < 2 && j >= 38) fl = "", region = 0;
      csv += fmt::format("{},0,{},{},{},{}\n", x, z, region, fl, fl.empty() ? "" : "0");
    }
  return parse_slice_csv(csv, "noisy.csv");
}

}  // namespace

// The colour scale's top is the field's, not the hot tiny cells'; they and everything above the
// top take the top colour, and the colour bar says ">=". A cell no photon reached is inside the
// mesh: the bottom colour, never the outside colour.
TEST(PlotSlices, ScaleTopIsRobustToHotCellsAndEmptyCellsInsideAreNotOutside) {
  SliceFigure f;
  f.panels = {noisy_slice()};
  const FigureSize size{900, 500};
  const SliceLayout l = slice_layout(f, size);
  // The 99.5 % area quantile of a field spread evenly over -5..-1 decades: near 1e-1, far
  // below the hot cells' 100 (log10 2).
  EXPECT_NEAR(l.log10_max, -1.0, 0.05);
  EXPECT_NEAR(l.log10_min, -5.0, 0.05);
  EXPECT_TRUE(l.clipped_high);
  EXPECT_TRUE(l.clipped_low) << "the empty cells lie below the bottom";
  EXPECT_EQ(l.top_label.rfind("\u2265 ", 0), 0u) << l.top_label;
  EXPECT_EQ(l.bottom_label.rfind("\u2264 ", 0), 0u) << l.bottom_label;
  EXPECT_TRUE(l.has_outside);
  EXPECT_EQ(hex_of(slice_cell_colour(100.0, 4, l)), hex_of(fluence_ramp(1.0)));
  EXPECT_EQ(hex_of(slice_cell_colour(0.0, 4, l)), hex_of(fluence_ramp(0.0)));
  EXPECT_EQ(hex_of(slice_cell_colour(std::nan(""), 0, l)), hex_of(kNoDataColour));
  // On the picture: the empty cells are the ramp's bottom, the corner outside is grey.
  const fs::path png = tocd::test::process_temp_path("slices.png");
  write_figure(f, png, size);
  const QImage img(QString::fromStdString(png.string()));
  ASSERT_FALSE(img.isNull());
  const PixelRect p = l.panels.at(0);
  auto at = [&](double x_mm, double z_mm) {  // the pixel at a point of the slice (4 mm high)
    return img.pixelColor(static_cast<int>(p.x + x_mm / 10.0 * p.width),
                          static_cast<int>(p.y + (1 - z_mm / 4.0) * p.height));
  };
  EXPECT_TRUE(same_colour(at(3.2, 1.05), fluence_ramp(0.0))) << at(3.2, 1.05).name().toStdString();
  EXPECT_TRUE(same_colour(at(0.1, 3.9), kNoDataColour)) << at(0.1, 3.9).name().toStdString();
  EXPECT_TRUE(same_colour(at(5.15, 2.05), fluence_ramp(1.0))) << at(5.15, 2.05).name().toStdString();
  // A plain field keeps its largest value as the top (nothing clipped, no ">=").
  SliceFigure plain;
  plain.panels = {noisy_slice()};
  for (double& v : plain.panels[0].fluence)
    if (v == 100.0 || v == 0.0) v = 1e-3;
  plain.top_quantile = 1.0;
  const SliceLayout q = slice_layout(plain, size);
  EXPECT_NEAR(q.log10_max, -1.0, 1e-6);
  EXPECT_FALSE(q.clipped_high);
  EXPECT_EQ(q.top_label, "0.1");
}

// The title states the state's own displacement and strain: sim 3 of the published study is
// 1.5 mm into 2.5 mm skin, 60 % (it used to be titled "50 % strain" by hand).
TEST(PlotSliceState, TitleStatesTheStrainOfTheStateThatWroteTheSlices) {
  const std::string study = R"({"kind": "tocdlab.study", "simulations": [
    {"sim": 2, "optics": "native", "config": {"baseline": false, "displacement_mm": 0.625, "thickness_mm": 2.5},
     "fluence": {"horizontal_csv": "fluence/sim02_horizontal.csv", "vertical_csv": "fluence/sim02_vertical.csv"}},
    {"sim": 3, "optics": "native", "config": {"baseline": false, "displacement_mm": 1.5, "thickness_mm": 2.5},
     "fluence": {"horizontal_csv": "fluence/sim03_horizontal.csv", "vertical_csv": "fluence/sim03_vertical.csv"}},
    {"sim": 0, "optics": "glass only", "config": {"baseline": true, "displacement_mm": 0, "thickness_mm": 2.5},
     "fluence": {"horizontal_csv": "fluence/sim00_horizontal.csv", "vertical_csv": "fluence/sim00_vertical.csv"}}]})";
  EXPECT_EQ(slice_state_title(study, {"/elsewhere/sim03_horizontal.csv", "sim03_vertical.csv"}, "s.json"),
            "fluence of sim 3 (native): 1.5 mm into 2.5 mm skin, 60 % strain");
  EXPECT_EQ(slice_state_title(study, {"sim02_vertical.csv"}, "s.json"),
            "fluence of sim 2 (native): 0.625 mm into 2.5 mm skin, 25 % strain");
  EXPECT_TRUE(contains(slice_state_title(study, {"sim00_vertical.csv"}, "s.json"), "glass only"));
  const std::string predict = R"({"T": 0.2, "config": {"baseline": false, "displacement_mm": 1.5,
      "thickness_mm": 2.5, "optics_model": "threshold", "compressed_optics": {"name": "cleared skin"}},
    "fluence": {"horizontal_csv": "d/prediction_horizontal.csv", "vertical_csv": "d/prediction_vertical.csv"}})";
  EXPECT_EQ(slice_state_title(predict, {"prediction_horizontal.csv"}, "p.json"),
            "fluence (cleared skin): 1.5 mm into 2.5 mm skin, 60 % strain");
  try {
    slice_state_title(study, {"other_horizontal.csv"}, "s.json");
    FAIL() << "slices no state wrote were given a title";
  } catch (const tocd::ConfigError& e) {
    EXPECT_TRUE(contains(e.what(), "s.json")) << e.what();
  }
}

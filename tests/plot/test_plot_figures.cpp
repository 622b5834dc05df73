// The figures of tocdlab plot, drawn headless and read back: pixels of PNGs, elements of SVGs.
#include <QColor>
#include <QFile>
#include <QImage>
#include <QXmlStreamReader>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <string>

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

// Relative luminance (ITU-R BT.709 weights on the 8-bit values): ordering only.
double luminance(QColor c) {
  return 0.2126 * c.red() + 0.7152 * c.green() + 0.0722 * c.blue();
}

std::string hex(Rgb c) {
  return QColor(c.r, c.g, c.b).name().toStdString();
}

// Elements of an SVG by tag name, counted only where the element (or its enclosing group)
// fills with `fill`. Parsing with QXmlStreamReader also proves the file is well-formed XML.
int count_filled(const fs::path& svg, const std::string& tag, const std::string& fill) {
  QFile f(QString::fromStdString(svg.string()));
  EXPECT_TRUE(f.open(QIODevice::ReadOnly));
  QXmlStreamReader xml(&f);
  std::vector<std::string> fills{""};  // the fill in effect, per open element
  int n = 0;
  while (!xml.atEnd()) {
    xml.readNext();
    if (xml.isStartElement()) {
      const auto attr = xml.attributes().value("fill").toString().toStdString();
      fills.push_back(attr.empty() ? fills.back() : attr);
      if (xml.name().toString().toStdString() == tag && fills.back() == fill) ++n;
    } else if (xml.isEndElement()) {
      fills.pop_back();
    }
  }
  EXPECT_FALSE(xml.hasError()) << xml.errorString().toStdString();
  return n;
}

BarFigure three_bars() {
  BarFigure f;
  f.title = "three bars";
  f.y_label = "value";
  f.labels = {"a", "b", "c"};
  f.values = {1.0, 2.0, 4.0};
  f.errors = {NAN, NAN, NAN};
  return f;
}

}  // namespace

TEST(PlotFormat, ExtensionDecidesAndUnknownIsRefused) {
  EXPECT_EQ(image_format_of("a/b.PNG"), ImageFormat::png);
  EXPECT_EQ(image_format_of("b.svg"), ImageFormat::svg);
  try {
    image_format_of("figure.jpg");
    FAIL() << "a .jpg was accepted";
  } catch (const tocd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("figure.jpg"), std::string::npos) << e.what();
  }
}

TEST(PlotRamp, LightnessRisesMonotonicallyFromViridisStartToEnd) {
  // Viridis' published end colours (#440154, #fde725).
  const Rgb lo = fluence_ramp(0.0), hi = fluence_ramp(1.0);
  EXPECT_EQ(hex(lo), "#440154");
  EXPECT_EQ(hex(hi), "#fde725");
  double last = -1;
  for (int k = 0; k <= 100; ++k) {
    const Rgb c = fluence_ramp(k / 100.0);
    const double l = luminance(QColor(c.r, c.g, c.b));
    EXPECT_GT(l, last) << "t = " << k / 100.0;
    last = l;
  }
}

TEST(PlotBars, BarHeightsAreProportionalToTheValues) {
  const FigureSize size{600, 400};
  const fs::path png = tocd::test::process_temp_path("bars.png");
  write_figure(three_bars(), png, size);
  QImage img(QString::fromStdString(png.string()));
  ASSERT_FALSE(img.isNull());
  EXPECT_EQ(img.width(), 600);
  EXPECT_EQ(img.height(), 400);
  const PixelRect area = chart_area(size);
  const double slot = area.width / 3;
  std::vector<int> heights;
  for (int k = 0; k < 3; ++k) {
    const int x = static_cast<int>(area.x + (k + 0.5) * slot);
    int h = 0;
    for (int y = 0; y < img.height(); ++y) h += same_colour(img.pixelColor(x, y), kMeasuredColour) ? 1 : 0;
    heights.push_back(h);
  }
  // Heights 1 : 2 : 4 of the value scale; +-2 px covers the antialiased edge rows.
  ASSERT_GT(heights[0], 10);
  EXPECT_NEAR(heights[1], 2.0 * heights[0], 2.0);
  EXPECT_NEAR(heights[2], 4.0 * heights[0], 3.0);
  // Between bars, just above the axis: background.
  const int between = static_cast<int>(area.x + slot);
  EXPECT_TRUE(
      same_colour(img.pixelColor(between, static_cast<int>(area.y + area.height - 3)), kBackgroundColour));
  // Along a row just above the axis: exactly three runs of bar colour.
  int runs = 0;
  bool in_bar = false;
  for (int x = static_cast<int>(area.x); x < static_cast<int>(area.x + area.width); ++x) {
    const bool bar =
        same_colour(img.pixelColor(x, static_cast<int>(area.y + area.height - 3)), kMeasuredColour);
    if (bar && !in_bar) ++runs;
    in_bar = bar;
  }
  EXPECT_EQ(runs, 3);
}

TEST(PlotBars, SvgIsXmlWithOneFilledElementPerBar) {
  const fs::path svg = tocd::test::process_temp_path("bars.svg");
  BarFigure f = three_bars();
  f.labels.push_back("d");
  f.values.push_back(3.0);
  f.errors.push_back(0.2);
  write_figure(f, svg);
  int bars = 0;
  for (const char* tag : {"rect", "path", "polygon"}) bars += count_filled(svg, tag, hex(kMeasuredColour));
  EXPECT_EQ(bars, 4);
}

// Bar lengths follow |dT| from the zero line, to the right for positive effects and to the left
// for negative ones; a bar within two standard errors of zero is drawn pale.
TEST(PlotTornado, BarsRunBothWaysFromZeroAndUnresolvedOnesArePale) {
  TornadoFigure f;
  f.labels = {"threshold: -0.6", "kinematics: plane strain", "pin length: 2.8"};
  f.values = {-0.010, 0.005, 0.0004};
  f.errors = {0.0004, 0.0004, 0.0004};
  const FigureSize size{800, 400};
  const fs::path png = tocd::test::process_temp_path("tornado.png");
  write_figure(f, png, size);
  QImage img(QString::fromStdString(png.string()));
  ASSERT_FALSE(img.isNull());
  const TornadoLayout layout = tornado_layout(f, size);
  auto row = [&](int k) {  // off the error bar, which runs through the bar's middle
    const PixelRect& b = layout.bars[static_cast<std::size_t>(k)];
    return static_cast<int>(b.y + b.height / 2 - 6);
  };
  auto run = [&](int y, Rgb colour, int& first, int& last) {
    first = -1, last = -1;
    for (int x = 0; x < img.width(); ++x)
      if (same_colour(img.pixelColor(x, y), colour)) {
        if (first < 0) first = x;
        last = x;
      }
    return first >= 0 ? last - first + 1 : 0;
  };
  int f0 = 0, l0 = 0, f1 = 0, l1 = 0, f2 = 0, l2 = 0;
  const int w0 = run(row(0), kMeasuredColour, f0, l0);
  const int w1 = run(row(1), kMeasuredColour, f1, l1);
  ASSERT_GT(w1, 10);
  EXPECT_NEAR(static_cast<double>(w0) / w1, 2.0, 0.05) << "lengths 0.010 : 0.005";
  // Between them: the 1 px zero line and an antialiased column on either side.
  EXPECT_NEAR(l0, f1, 4) << "the negative bar ends where the positive one starts: at zero";
  EXPECT_EQ(run(row(2), kMeasuredColour, f2, l2), 0);
  EXPECT_GT(run(row(2), kUnresolvedColour, f2, l2), 0);
  EXPECT_NEAR(f2, f1, 2);
  f.errors.pop_back();
  EXPECT_THROW(write_figure(f, png, size), tocd::ConfigError);
}

TEST(PlotBars, RefusesNonFiniteValuesAndMismatchedLabels) {
  BarFigure f = three_bars();
  f.values[1] = NAN;
  EXPECT_THROW(write_figure(f, tocd::test::process_temp_path("x.png")), tocd::ConfigError);
  f = three_bars();
  f.labels.pop_back();
  EXPECT_THROW(write_figure(f, tocd::test::process_temp_path("x.png")), tocd::ConfigError);
}

namespace {

// A 40 x 20 point x-z slice: region 1 (fluence 1e-4) left of x = 0, region 2 (fluence 1)
// right of it, and the top-left 5 x 5 points outside the mesh.
Slice two_region_slice() {
  std::string csv = "x_mm,y_mm,z_mm,region,fluence,fluence_se\n";
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 40; ++i) {
      const double x = -1.95 + 0.1 * i, z = 0.05 + 0.1 * j;
      const bool outside = i < 5 && j >= 15;
      const int region = outside ? 0 : (x < 0 ? 1 : 2);
      const std::string fl = outside ? "" : (x < 0 ? "1e-4" : "1");
      csv += std::to_string(x) + ",0," + std::to_string(z) + "," + std::to_string(region) + "," + fl + "," +
             (outside ? "" : "0") + "\n";
    }
  return parse_slice_csv(csv, "two_regions.csv");
}

}  // namespace

TEST(PlotSlices, LogColoursRegionOutlineNoDataAndMonotoneColourBar) {
  SliceFigure f;
  f.panels = {two_region_slice()};
  f.decades = 6;
  const FigureSize size{800, 500};
  const SliceLayout layout = slice_layout(f, size);
  // The scale: 1 down to the smallest positive value (1e-4), less than the 6 decades asked.
  EXPECT_DOUBLE_EQ(layout.log10_max, 0.0);
  EXPECT_DOUBLE_EQ(layout.log10_min, -4.0);
  const fs::path png = tocd::test::process_temp_path("slices.png");
  write_figure(f, png, size);
  QImage img(QString::fromStdString(png.string()));
  ASSERT_FALSE(img.isNull());
  const PixelRect p = layout.panels.at(0);
  // 4 mm by 2 mm keeps its 2:1 aspect.
  EXPECT_NEAR(p.width / p.height, 2.0, 0.01);
  auto at = [&](double fx, double fy) {  // fractions of the panel, y up
    return img.pixelColor(static_cast<int>(p.x + fx * p.width), static_cast<int>(p.y + (1 - fy) * p.height));
  };
  // Low end of the scale on the left (viridis start), high end on the right (viridis end).
  EXPECT_TRUE(same_colour(at(0.25, 0.3), fluence_ramp(0.0))) << at(0.25, 0.3).name().toStdString();
  EXPECT_TRUE(same_colour(at(0.75, 0.3), fluence_ramp(1.0))) << at(0.75, 0.3).name().toStdString();
  EXPECT_TRUE(same_colour(at(0.05, 0.95), kNoDataColour)) << at(0.05, 0.95).name().toStdString();
  // The region boundary at x = 0 (the panel's middle) is outlined: some pixel of the column
  // within one pixel of it has the outline colour.
  const int mid = static_cast<int>(p.x + 0.5 * p.width);
  const int y = static_cast<int>(p.y + 0.5 * p.height);
  bool outlined = false;
  for (int dx = -1; dx <= 1; ++dx) outlined |= luminance(img.pixelColor(mid + dx, y)) > 230;
  EXPECT_TRUE(outlined);
  // Colour bar: lightness never falls from bottom to top; bottom and top are the ramp's ends.
  const PixelRect bar = layout.colour_bar;
  const int bx = static_cast<int>(bar.x + bar.width / 2);
  double last = -1;
  for (int yy = static_cast<int>(bar.y + bar.height) - 2; yy > static_cast<int>(bar.y) + 1; --yy) {
    const double l = luminance(img.pixelColor(bx, yy));
    EXPECT_GE(l, last - 0.5) << "colour bar row " << yy;
    last = l;
  }
  EXPECT_TRUE(
      same_colour(img.pixelColor(bx, static_cast<int>(bar.y + bar.height) - 2), fluence_ramp(0.0), 8));
  EXPECT_TRUE(same_colour(img.pixelColor(bx, static_cast<int>(bar.y) + 2), fluence_ramp(1.0), 8));
}

TEST(PlotSlices, RefusesSlicesWithoutPositiveFluence) {
  Slice s = two_region_slice();
  for (double& v : s.fluence) v = 0.0;
  SliceFigure f;
  f.panels = {s};
  EXPECT_THROW(write_figure(f, tocd::test::process_temp_path("zero.png")), tocd::ConfigError);
}

TEST(PlotCompare, SvgHasOneMarkerPerMeasuredAndPerPredictedStep) {
  CompareFigure f;
  f.title = "run 1";
  const double nan = std::numeric_limits<double>::quiet_NaN();
  f.steps = {{0, 0.5, 0.30, 0.31, 0.01},
             {1, 1.0, 0.35, 0.36, 0.01},
             {2, 1.5, 0.41, nan, nan},
             {3, 2.0, nan, 0.45, 0.02}};
  const fs::path svg = tocd::test::process_temp_path("compare.svg");
  write_figure(f, svg);
  // Three measured steps and three predictions, plus one glyph of each in the legend.
  EXPECT_EQ(
      count_filled(svg, "ellipse", hex(kMeasuredColour)) + count_filled(svg, "circle", hex(kMeasuredColour)),
      3 + 1);
  int predicted = 0;
  for (const char* tag : {"rect", "path", "polygon"})
    predicted += count_filled(svg, tag, hex(kPredictedColour));
  EXPECT_EQ(predicted, 3 + 1);
}

TEST(PlotFit, SvgHasEveryDataPointAndTheCurve) {
  FitFigure f;
  for (int k = 0; k < 12; ++k) {
    const double e = 0.05 * k;
    f.strain.push_back(e);
    f.stress_MPa.push_back(0.01 * e * e);
    f.curve_strain.push_back(e);
    f.curve_stress_MPa.push_back(0.0105 * e * e);
  }
  f.curve_label = "law";
  const fs::path svg = tocd::test::process_temp_path("fit.svg");
  write_figure(f, svg);
  EXPECT_EQ(
      count_filled(svg, "ellipse", hex(kMeasuredColour)) + count_filled(svg, "circle", hex(kMeasuredColour)),
      12 + 1);
  // A PNG of the same: the curve's colour appears inside the chart area.
  const FigureSize size{640, 480};
  const fs::path png = tocd::test::process_temp_path("fit.png");
  write_figure(f, png, size);
  QImage img(QString::fromStdString(png.string()));
  const PixelRect a = chart_area(size);
  int curve_pixels = 0;
  for (int y = static_cast<int>(a.y); y < static_cast<int>(a.y + a.height); ++y)
    for (int x = static_cast<int>(a.x + a.width / 2); x < static_cast<int>(a.x + a.width); ++x)
      curve_pixels += same_colour(img.pixelColor(x, y), kPredictedColour, 10) ? 1 : 0;
  EXPECT_GT(curve_pixels, 100);
}

TEST(PlotOutput, UnwritableFolderIsAClearError) {
  try {
    write_figure(three_bars(), "/nonexistent-folder/bars.png");
    FAIL() << "no error";
  } catch (const tocd::Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/bars.png"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists("/nonexistent-folder/bars.png.part"));
}

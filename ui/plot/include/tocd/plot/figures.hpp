#pragma once

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace tocd::plot {

/// Pixels of a PNG; user units (1 unit = 1 px) of an SVG.
struct FigureSize {
  int width = 900;
  int height = 600;
};

enum class ImageFormat { png, svg };

/// The format named by the file's extension (.png or .svg, any case). Throws tocd::ConfigError
/// naming the file otherwise.
ImageFormat image_format_of(const std::filesystem::path& path);

/// A rectangle in figure pixels, y down (as in the image).
struct PixelRect {
  double x = 0, y = 0, width = 0, height = 0;
};

/// One fluence slice on a regular grid: nx by ny cells over [x_min, x_max] x [y_min, y_max],
/// row-major with row 0 at y_min. Fluence NaN marks points outside the mesh; region 0 too. A
/// fluence of 0 inside the mesh is a cell no photon reached: data, the bottom of the scale.
struct Slice {
  std::string title;
  std::string x_label = "x (mm)", y_label = "z (mm)";
  int nx = 0, ny = 0;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  std::vector<double> fluence;
  std::vector<int> region;
};

/// Slices side by side on one logarithmic colour scale (one colour bar), region boundaries
/// outlined, so equal colours mean equal fluence in every panel.
struct SliceFigure {
  std::string title;
  std::vector<Slice> panels;
  double decades = 6.0;  ///< the colour scale spans this many decades below its top
  /// The colour scale's top: this quantile of the cells' fluence, weighted by cell area. Not
  /// the maximum: the smallest tets (at the pin tip) hold few photon tracks, and their noise
  /// would set the top and push the rest of the field into the dark end.
  double top_quantile = 0.995;
};

/// Where a slice figure puts its parts and what its colours mean: one rectangle per panel (the
/// data area) and the colour bar, whose top is log10_max and bottom log10_min. Cells above the
/// top are drawn in the top colour (clipped_high: the bar's top label reads ">="), cells below
/// the bottom and cells no photon reached in the bottom colour (clipped_low: "<=").
struct SliceLayout {
  std::vector<PixelRect> panels;
  PixelRect colour_bar;
  double log10_min = 0, log10_max = 0;
  bool clipped_high = false, clipped_low = false;
  bool has_outside = false;               ///< some cell lies outside the mesh (legend entry)
  std::string top_label, bottom_label;    ///< the colour bar's end labels
  std::vector<std::string> panel_titles;  ///< above each panel
};
SliceLayout slice_layout(const SliceFigure& figure, FigureSize size);

/// Measured and predicted transmission per step of a run; predictions carry a standard error.
struct StepPoint {
  int step = 0;
  double displacement_mm = 0;
  double measured_T = 0;                       ///< NaN: not measured (step not completed)
  double predicted_T = 0, predicted_T_se = 0;  ///< NaN: no prediction
  /// Standard error of the measured T: of the mean power over the recording window, divided
  /// by the baseline power (the database's step_comparison view). NaN: none, no error bar.
  double measured_T_se = std::numeric_limits<double>::quiet_NaN();
};
struct CompareFigure {
  std::string title;
  std::vector<StepPoint> steps;
};

/// A marker of the compare figure and its error bar, in figure pixels. The bar is drawn at the
/// marker's own x, from error_low_y to error_high_y (NaN: no error bar).
struct CompareMarker {
  int step = 0;
  double x = 0, y = 0;
  double error_low_y = std::numeric_limits<double>::quiet_NaN();
  double error_high_y = std::numeric_limits<double>::quiet_NaN();
};

/// What the compare figure draws: its data area, the measured and the predicted markers and
/// the legend's lines (which say what the error bars are).
struct CompareLayout {
  PixelRect area;
  double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;  ///< the axes' data ranges
  std::vector<CompareMarker> measured, predicted;
  std::vector<std::string> legend;
};
CompareLayout compare_layout(const CompareFigure& figure, FigureSize size);
inline constexpr double kCompareMarkerRadius = 5.5;  ///< an 11 px marker: its centre is a pixel's

/// Stress-strain points and a fitted law sampled as a curve (both nominal, compression positive).
struct FitFigure {
  std::string title;
  std::vector<double> strain, stress_MPa;              ///< the data
  std::vector<double> curve_strain, curve_stress_MPa;  ///< the fitted law
  std::string curve_label;
};

/// One bar per label with an optional error bar (NaN: none). A label's '\n' starts a new line;
/// lines wrap at spaces to the bar's slot.
struct BarFigure {
  std::string title, y_label, x_label;
  std::vector<std::string> labels;
  std::vector<double> values, errors;
};

/// What a bar chart draws, in figure pixels: the data area (its bottom margin grown to hold
/// the labels), each bar, its error bar's ends (NaN: none) and its label, wrapped into lines
/// that fit the bar's slot, or turned upright (rotated 90 degrees) when a word does not fit.
/// label_boxes are the extents of the label texts; no two overlap and none leaves the figure.
struct BarLayout {
  PixelRect area;
  double y_lo = 0, y_hi = 1;  ///< the value axis' range
  std::vector<PixelRect> bars;
  std::vector<double> error_low_y, error_high_y;
  std::vector<std::vector<std::string>> label_lines;
  std::vector<PixelRect> label_boxes;
  bool labels_rotated = false;
  double line_height = 0;
};
BarLayout bar_layout(const BarFigure& figure, FigureSize size);

/// A tornado chart: one horizontal bar per factor, its effect (dT) with +- its standard error,
/// largest |effect| on top. Bars whose effect is within `resolution` standard errors of zero
/// are drawn pale: below the Monte Carlo error.
struct TornadoFigure {
  std::string title, x_label;
  std::vector<std::string> labels;
  std::vector<double> values, errors;
  double resolution = 2.0;
};

/// What a tornado chart draws: the data area, one bar per factor (resolved: beyond
/// `resolution` standard errors, drawn dark; else pale) and the key's two lines, dark first.
struct TornadoLayout {
  PixelRect area;
  std::vector<PixelRect> bars;
  std::vector<bool> resolved;
  std::vector<std::string> key;
  std::vector<PixelRect> key_boxes;  ///< each key entry (swatch and text), below the x axis' label
};
TornadoLayout tornado_layout(const TornadoFigure& figure, FigureSize size);

/// The data area of the charts (compare, fit, bars) for a figure of `size`.
PixelRect chart_area(FigureSize size);

/// Write the figure to `path` as PNG or SVG (by extension). Throw tocd::ConfigError for an
/// empty or inconsistent figure and tocd::Error when the file cannot be written.
void write_figure(const SliceFigure& figure, const std::filesystem::path& path, FigureSize size = {});
void write_figure(const CompareFigure& figure, const std::filesystem::path& path, FigureSize size = {});
void write_figure(const FitFigure& figure, const std::filesystem::path& path, FigureSize size = {});
void write_figure(const BarFigure& figure, const std::filesystem::path& path, FigureSize size = {});
void write_figure(const TornadoFigure& figure, const std::filesystem::path& path, FigureSize size = {});

/// The colour ramp of the fluence scale, t in [0, 1] (clamped) from low to high: viridis,
/// whose lightness rises monotonically, so it reads correctly in grey too. {r, g, b} 0..255.
struct Rgb {
  int r = 0, g = 0, b = 0;
};
Rgb fluence_ramp(double t);

/// The colour a slice cell is drawn in on the scale of `layout`: kNoDataColour outside the
/// mesh (fluence NaN or region 0) only; every cell inside it gets a colour of the ramp.
Rgb slice_cell_colour(double fluence, int region, const SliceLayout& layout);

/// The fixed colours of the figures, for readers of the pictures (and their tests).
inline constexpr Rgb kNoDataColour{64, 64, 64};  ///< slice points outside the mesh
inline constexpr Rgb kRegionOutlineColour{255, 255, 255};
inline constexpr Rgb kMeasuredColour{31, 119, 180};  ///< measured points, data points, bars
inline constexpr Rgb kPredictedColour{214, 39, 40};  ///< predictions and fitted curves
inline constexpr Rgb kBackgroundColour{255, 255, 255};
inline constexpr Rgb kUnresolvedColour{174, 199, 232};  ///< tornado bars below their error

}  // namespace tocd::plot

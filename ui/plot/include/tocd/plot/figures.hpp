#pragma once

#include <filesystem>
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
/// row-major with row 0 at y_min. Fluence NaN marks points outside the mesh; region 0 too.
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
  double decades = 6.0;  ///< the colour scale spans this many decades below the largest fluence
};

/// Where a slice figure puts its parts: one rectangle per panel (the data area) and the colour
/// bar, whose top is the largest fluence (log10_max) and bottom log10_min.
struct SliceLayout {
  std::vector<PixelRect> panels;
  PixelRect colour_bar;
  double log10_min = 0, log10_max = 0;
};
SliceLayout slice_layout(const SliceFigure& figure, FigureSize size);

/// Measured and predicted transmission per step of a run; predictions carry a standard error.
struct StepPoint {
  int step = 0;
  double displacement_mm = 0;
  double measured_T = 0;                       ///< NaN: not measured (step not completed)
  double predicted_T = 0, predicted_T_se = 0;  ///< NaN: no prediction
};
struct CompareFigure {
  std::string title;
  std::vector<StepPoint> steps;
};

/// Stress-strain points and a fitted law sampled as a curve (both nominal, compression positive).
struct FitFigure {
  std::string title;
  std::vector<double> strain, stress_MPa;              ///< the data
  std::vector<double> curve_strain, curve_stress_MPa;  ///< the fitted law
  std::string curve_label;
};

/// One bar per label with an optional error bar (NaN: none).
struct BarFigure {
  std::string title, y_label;
  std::vector<std::string> labels;
  std::vector<double> values, errors;
};

/// A tornado chart: one horizontal bar per factor, its effect (dT) with +- its standard error,
/// largest |effect| on top. Bars whose effect is within `resolution` standard errors of zero
/// are drawn pale: below the Monte Carlo error.
struct TornadoFigure {
  std::string title, x_label;
  std::vector<std::string> labels;
  std::vector<double> values, errors;
  double resolution = 2.0;
};

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

/// The fixed colours of the figures, for readers of the pictures (and their tests).
inline constexpr Rgb kNoDataColour{64, 64, 64};  ///< slice points outside the mesh
inline constexpr Rgb kRegionOutlineColour{255, 255, 255};
inline constexpr Rgb kMeasuredColour{31, 119, 180};  ///< measured points, data points, bars
inline constexpr Rgb kPredictedColour{214, 39, 40};  ///< predictions and fitted curves
inline constexpr Rgb kBackgroundColour{255, 255, 255};
inline constexpr Rgb kUnresolvedColour{174, 199, 232};  ///< tornado bars below their error

}  // namespace tocd::plot

#include <algorithm>
#include <cmath>
#include <limits>

#include "axes.hpp"
#include "canvas.hpp"
#include "legend.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/figures.hpp"

namespace tocd::plot {
namespace {

constexpr double kMarkerRadius = kCompareMarkerRadius;

// The centre of the pixel `v` falls in. Markers and error bars are placed on pixel centres:
// an 11 px marker then covers whole pixels and a 1 px bar one column, the same column as the
// marker's middle, in every renderer.
double pixel_centre(double v) {
  return std::floor(v) + 0.5;
}

void error_bar(QPainter& p, const CompareMarker& m) {
  if (!std::isfinite(m.error_low_y) || !std::isfinite(m.error_high_y)) return;
  p.setPen(QPen(Qt::black, 1.0, Qt::SolidLine, Qt::FlatCap));
  p.drawLine(QPointF(m.x, m.error_low_y), QPointF(m.x, m.error_high_y));
  p.drawLine(QPointF(m.x - 4.5, m.error_low_y), QPointF(m.x + 4.5, m.error_low_y));
  p.drawLine(QPointF(m.x - 4.5, m.error_high_y), QPointF(m.x + 4.5, m.error_high_y));
}

void measured_glyph(QPainter& p, QPointF c) {
  p.setPen(QPen(Qt::black, 0.8));
  p.setBrush(detail::qcolour(kMeasuredColour));
  p.drawEllipse(c, kMarkerRadius - 0.4, kMarkerRadius - 0.4);
}

void predicted_glyph(QPainter& p, QPointF c) {
  p.setPen(QPen(Qt::black, 0.8));
  p.setBrush(detail::qcolour(kPredictedColour));
  const double r = kMarkerRadius - 0.4;  // the outline's middle: the outline ends on the 11 px
  p.drawRect(QRectF(c.x() - r, c.y() - r, 2 * r, 2 * r));
}

}  // namespace

CompareLayout compare_layout(const CompareFigure& figure, FigureSize size) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto se_of = [](double se) { return std::isfinite(se) && se > 0 ? se : 0.0; };
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  std::size_t values = 0;
  for (const auto& s : figure.steps) {
    x_lo = std::min(x_lo, s.displacement_mm), x_hi = std::max(x_hi, s.displacement_mm);
    if (std::isfinite(s.measured_T)) {
      const double se = se_of(s.measured_T_se);
      y_lo = std::min(y_lo, s.measured_T - se), y_hi = std::max(y_hi, s.measured_T + se), ++values;
    }
    if (std::isfinite(s.predicted_T)) {
      const double se = se_of(s.predicted_T_se);
      y_lo = std::min(y_lo, s.predicted_T - se), y_hi = std::max(y_hi, s.predicted_T + se), ++values;
    }
  }
  if (values == 0) throw ConfigError("compare figure: no step has a measured or predicted transmission");
  // Transmission is a fraction: the axis starts at 0 so ratios between steps read true.
  // Half a marker-pair of room at both ends, so the first and last steps clear the frame.
  const double pad = x_hi > x_lo ? 0.05 * (x_hi - x_lo) : 0.1;
  const auto x = detail::nice_axis(x_lo - pad, x_hi + pad);
  const auto y = detail::nice_axis(std::min(0.0, y_lo), y_hi * 1.15);
  CompareLayout out;
  out.area = chart_area(size);
  out.x_lo = x.lo, out.x_hi = x.hi, out.y_lo = y.lo, out.y_hi = y.hi;
  const QRectF area = detail::qrect(out.area);
  auto px = [&](double v) { return detail::map(x, v, area.left(), area.right()); };
  auto py = [&](double v) { return detail::map(y, v, area.bottom(), area.top()); };
  // The measured point and the prediction of a step stand side by side, astride its
  // displacement, so neither hides the other; each error bar is on its own marker's centre.
  auto marker = [&](const StepPoint& s, double T, double se, double dx) {
    CompareMarker m;
    m.step = s.step;
    m.x = pixel_centre(px(s.displacement_mm) + dx);
    m.y = py(T);
    if (std::isfinite(se) && se > 0)
      m.error_low_y = py(T - se), m.error_high_y = py(T + se);
    else
      m.error_low_y = m.error_high_y = nan;
    return m;
  };
  bool measured_errors = false;
  for (const auto& s : figure.steps) {
    if (std::isfinite(s.measured_T)) {
      out.measured.push_back(marker(s, s.measured_T, s.measured_T_se, -1.6 * kMarkerRadius));
      measured_errors = measured_errors || std::isfinite(out.measured.back().error_low_y);
    }
    if (std::isfinite(s.predicted_T))
      out.predicted.push_back(marker(s, s.predicted_T, s.predicted_T_se, 1.6 * kMarkerRadius));
  }
  out.legend = {measured_errors
                    ? "measured (\u00b11 standard error of the mean power in the recording window; "
                      "a bar shorter than the marker is hidden)"
                    : "measured",
                "predicted (FE + Monte Carlo, \u00b11 Monte Carlo standard error)"};
  return out;
}

void write_figure(const CompareFigure& figure, const std::filesystem::path& path, FigureSize size) {
  const CompareLayout layout = compare_layout(figure, size);
  const QRectF area = detail::qrect(layout.area);
  const auto x = detail::nice_axis(layout.x_lo, layout.x_hi), y = detail::nice_axis(layout.y_lo, layout.y_hi);
  detail::render_to_file(path, size, [&](QPainter& p) {
    detail::draw_title(p, QRectF(0, 0, size.width, size.height), QString::fromStdString(figure.title));
    detail::draw_axes(p, area, x, y, QStringLiteral("pin displacement (mm)"),
                      QStringLiteral("transmission T = power / baseline power"));
    // Bars first, markers over them: a bar shorter than its marker is hidden, not drawn over it.
    for (const auto& m : layout.predicted) error_bar(p, m);
    for (const auto& m : layout.measured) error_bar(p, m);
    for (const auto& m : layout.predicted) predicted_glyph(p, QPointF(m.x, m.y));
    for (const auto& m : layout.measured) measured_glyph(p, QPointF(m.x, m.y));
    detail::draw_legend(p, area,
                        {{QString::fromStdString(layout.legend[0]), measured_glyph},
                         {QString::fromStdString(layout.legend[1]), predicted_glyph}});
  });
}

}  // namespace tocd::plot

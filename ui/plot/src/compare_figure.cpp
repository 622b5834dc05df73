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

constexpr double kMarkerRadius = 5;

void measured_glyph(QPainter& p, QPointF c) {
  p.setPen(QPen(Qt::black, 0.8));
  p.setBrush(detail::qcolour(kMeasuredColour));
  p.drawEllipse(c, kMarkerRadius, kMarkerRadius);
}

void predicted_glyph(QPainter& p, QPointF c) {
  p.setPen(QPen(Qt::black, 0.8));
  p.setBrush(detail::qcolour(kPredictedColour));
  p.drawRect(QRectF(c.x() - kMarkerRadius, c.y() - kMarkerRadius, 2 * kMarkerRadius, 2 * kMarkerRadius));
}

}  // namespace

void write_figure(const CompareFigure& figure, const std::filesystem::path& path, FigureSize size) {
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  std::size_t values = 0;
  for (const auto& s : figure.steps) {
    x_lo = std::min(x_lo, s.displacement_mm), x_hi = std::max(x_hi, s.displacement_mm);
    if (std::isfinite(s.measured_T))
      y_lo = std::min(y_lo, s.measured_T), y_hi = std::max(y_hi, s.measured_T), ++values;
    if (std::isfinite(s.predicted_T)) {
      const double se = std::isfinite(s.predicted_T_se) ? s.predicted_T_se : 0.0;
      y_lo = std::min(y_lo, s.predicted_T - se), y_hi = std::max(y_hi, s.predicted_T + se), ++values;
    }
  }
  if (values == 0) throw ConfigError("compare figure: no step has a measured or predicted transmission");
  // Transmission is a fraction: the axis starts at 0 so ratios between steps read true.
  // Half a marker-pair of room at both ends, so the first and last steps clear the frame.
  const double pad = x_hi > x_lo ? 0.05 * (x_hi - x_lo) : 0.1;
  const auto x = detail::nice_axis(x_lo - pad, x_hi + pad);
  const auto y = detail::nice_axis(std::min(0.0, y_lo), y_hi * 1.15);
  const QRectF area = detail::qrect(chart_area(size));
  detail::render_to_file(path, size, [&](QPainter& p) {
    detail::draw_title(p, QRectF(0, 0, size.width, size.height), QString::fromStdString(figure.title));
    detail::draw_axes(p, area, x, y, QStringLiteral("pin displacement (mm)"),
                      QStringLiteral("transmission T"));
    auto px = [&](double v) { return detail::map(x, v, area.left(), area.right()); };
    auto py = [&](double v) { return detail::map(y, v, area.bottom(), area.top()); };
    for (const auto& s : figure.steps) {
      if (!std::isfinite(s.predicted_T)) continue;
      // Error bar: the prediction +- one Monte Carlo standard error, with caps.
      const double se = std::isfinite(s.predicted_T_se) ? s.predicted_T_se : 0.0;
      const double cx = px(s.displacement_mm) + kMarkerRadius * 1.6;  // beside the measured point
      p.setPen(QPen(Qt::black, 1.2));
      p.drawLine(QPointF(cx, py(s.predicted_T - se)), QPointF(cx, py(s.predicted_T + se)));
      p.drawLine(QPointF(cx - 4, py(s.predicted_T - se)), QPointF(cx + 4, py(s.predicted_T - se)));
      p.drawLine(QPointF(cx - 4, py(s.predicted_T + se)), QPointF(cx + 4, py(s.predicted_T + se)));
      predicted_glyph(p, QPointF(cx, py(s.predicted_T)));
    }
    for (const auto& s : figure.steps)
      if (std::isfinite(s.measured_T))
        measured_glyph(p, QPointF(px(s.displacement_mm) - kMarkerRadius * 1.6, py(s.measured_T)));
    detail::draw_legend(p, area,
                        {{QStringLiteral("measured"), measured_glyph},
                         {QStringLiteral("predicted (FE + Monte Carlo, \u00b11 s.e.)"), predicted_glyph}});
  });
}

}  // namespace tocd::plot

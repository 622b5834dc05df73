#include <QFontMetricsF>
#include <algorithm>
#include <cmath>

#include "axes.hpp"
#include "canvas.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/figures.hpp"

namespace tocd::plot {

void write_figure(const TornadoFigure& figure, const std::filesystem::path& path, FigureSize size) {
  const std::size_t n = figure.values.size();
  if (n == 0) throw ConfigError("tornado chart: no bars to draw");
  if (figure.labels.size() != n || figure.errors.size() != n)
    throw ConfigError("tornado chart: labels, values and errors differ in number");
  double lo = 0, hi = 0;  // bars grow from zero
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(figure.values[k]))
      throw ConfigError("tornado chart: the value of '" + figure.labels[k] + "' is not a number");
    const double e = std::isfinite(figure.errors[k]) ? figure.errors[k] : 0.0;
    lo = std::min(lo, figure.values[k] - e), hi = std::max(hi, figure.values[k] + e);
  }
  const auto x = detail::nice_axis(lo, hi);
  detail::render_to_file(path, size, [&](QPainter& p) {
    // The labels sit left of the bars: the chart area starts after the widest of them.
    const QFontMetricsF fm(p.font());
    double label_width = 0;
    for (const auto& l : figure.labels)
      label_width = std::max(label_width, fm.horizontalAdvance(QString::fromStdString(l)));
    const PixelRect base = chart_area(size);
    const double left = std::min(label_width + 16, 0.5 * size.width);
    const QRectF area(left, base.y, size.width - left - 30, base.height);
    detail::draw_title(p, QRectF(0, 0, size.width, size.height), QString::fromStdString(figure.title));
    detail::draw_axes(p, area, x, detail::Axis{0, 1, {}}, QString::fromStdString(figure.x_label), QString());
    auto px = [&](double v) { return detail::map(x, v, area.left(), area.right()); };
    const double slot = area.height() / static_cast<double>(n), thick = 0.7 * slot;
    for (std::size_t k = 0; k < n; ++k) {
      const double cy = area.top() + (static_cast<double>(k) + 0.5) * slot;
      const double v = figure.values[k], e = figure.errors[k];
      const bool resolved = std::isfinite(e) && std::abs(v) > figure.resolution * e;
      const QRectF bar(QPointF(px(std::min(v, 0.0)), cy - thick / 2),
                       QPointF(px(std::max(v, 0.0)), cy + thick / 2));
      p.fillRect(bar, detail::qcolour(resolved ? kMeasuredColour : kUnresolvedColour));
      if (std::isfinite(e) && e > 0) {
        p.setPen(QPen(Qt::black, 1.2));
        p.drawLine(QPointF(px(v - e), cy), QPointF(px(v + e), cy));
        p.drawLine(QPointF(px(v - e), cy - 4), QPointF(px(v - e), cy + 4));
        p.drawLine(QPointF(px(v + e), cy - 4), QPointF(px(v + e), cy + 4));
      }
      p.setPen(Qt::black);
      p.drawText(QRectF(0, cy - slot / 2, area.left() - 8, slot), Qt::AlignRight | Qt::AlignVCenter,
                 QString::fromStdString(figure.labels[k]));
    }
    p.setPen(QPen(Qt::black, 1.0));  // zero: the base prediction
    p.drawLine(QPointF(px(0), area.top()), QPointF(px(0), area.bottom()));
  });
}

}  // namespace tocd::plot

#include <QFontMetricsF>
#include <algorithm>
#include <cmath>

#include "axes.hpp"
#include "canvas.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/figures.hpp"

namespace tocd::plot {

void write_figure(const BarFigure& figure, const std::filesystem::path& path, FigureSize size) {
  const std::size_t n = figure.values.size();
  if (n == 0) throw ConfigError("bar chart: no bars to draw");
  if (figure.labels.size() != n || (!figure.errors.empty() && figure.errors.size() != n))
    throw ConfigError("bar chart: labels, values and errors differ in number");
  double lo = 0, hi = 0;  // bars grow from zero
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(figure.values[k]))
      throw ConfigError("bar chart: the value of '" + figure.labels[k] + "' is not a number");
    const double e = figure.errors.empty() || !std::isfinite(figure.errors[k]) ? 0.0 : figure.errors[k];
    lo = std::min(lo, figure.values[k] - e), hi = std::max(hi, figure.values[k] + e);
  }
  const auto y = detail::nice_axis(lo, hi);
  const QRectF area = detail::qrect(chart_area(size));
  detail::render_to_file(path, size, [&](QPainter& p) {
    detail::draw_title(p, QRectF(0, 0, size.width, size.height), QString::fromStdString(figure.title));
    detail::Axis x{0, 1, {}};
    detail::draw_axes(p, area, x, y, QString(), QString::fromStdString(figure.y_label));
    auto py = [&](double v) { return detail::map(y, v, area.bottom(), area.top()); };
    const double slot = area.width() / static_cast<double>(n), width = 0.7 * slot;
    const QFontMetricsF fm(p.font());
    for (std::size_t k = 0; k < n; ++k) {
      const double cx = area.left() + (static_cast<double>(k) + 0.5) * slot;
      const double v = figure.values[k];
      const QRectF bar(QPointF(cx - width / 2, py(std::max(v, 0.0))),
                       QPointF(cx + width / 2, py(std::min(v, 0.0))));
      p.fillRect(bar, detail::qcolour(kMeasuredColour));
      if (!figure.errors.empty() && std::isfinite(figure.errors[k]) && figure.errors[k] > 0) {
        const double e = figure.errors[k];
        p.setPen(QPen(Qt::black, 1.2));
        p.drawLine(QPointF(cx, py(v - e)), QPointF(cx, py(v + e)));
        p.drawLine(QPointF(cx - 5, py(v - e)), QPointF(cx + 5, py(v - e)));
        p.drawLine(QPointF(cx - 5, py(v + e)), QPointF(cx + 5, py(v + e)));
      }
      p.setPen(Qt::black);
      const QString label = QString::fromStdString(figure.labels[k]);
      p.drawText(QRectF(cx - slot / 2, area.bottom() + 6, slot, 2.5 * fm.height()),
                 Qt::AlignHCenter | Qt::AlignTop | Qt::TextWordWrap, label);
    }
    if (lo < 0) {  // the zero line, when bars go both ways
      p.setPen(QPen(Qt::black, 1.0));
      p.drawLine(QPointF(area.left(), py(0)), QPointF(area.right(), py(0)));
    }
  });
}

}  // namespace tocd::plot

#include "axes.hpp"

#include <QFontMetricsF>
#include <algorithm>
#include <cmath>

#include "tocd/plot/figures.hpp"

namespace tocd::plot {

PixelRect chart_area(FigureSize size) {
  // Room for tick labels and the axis label on the left and below, the title above, the
  // legend inside the frame.
  const double left = 90, right = 30, top = 50, bottom = 70;
  return {left, top, size.width - left - right, size.height - top - bottom};
}

namespace detail {

Axis nice_axis(double lo, double hi, int target_ticks) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) lo = 0, hi = 1;
  if (hi < lo) std::swap(lo, hi);
  if (hi - lo < 1e-12 * std::max(1.0, std::abs(hi))) {
    const double pad = lo == 0 ? 1.0 : 0.1 * std::abs(lo);
    lo -= pad, hi += pad;
  }
  // Step = 1, 2 or 5 times a power of ten, the smallest giving at most target_ticks intervals.
  const double raw = (hi - lo) / std::max(1, target_ticks);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * mag;
    if (step >= raw) break;
  }
  Axis a;
  a.lo = std::floor(lo / step) * step;
  a.hi = std::ceil(hi / step) * step;
  for (double t = a.lo; t <= a.hi + 0.5 * step; t += step)
    a.ticks.push_back(std::abs(t) < 1e-9 * step ? 0.0 : t);
  return a;
}

QString tick_text(double v) {
  return QString::number(v, 'g', 4);
}

void draw_axes(QPainter& p, const QRectF& area, const Axis& x, const Axis& y, const QString& x_label,
               const QString& y_label) {
  p.save();
  p.setPen(QPen(Qt::black, 1.0));
  p.setBrush(Qt::NoBrush);
  p.drawRect(area);
  const QFontMetricsF fm(p.font());
  for (double t : x.ticks) {
    const double px = map(x, t, area.left(), area.right());
    p.drawLine(QPointF(px, area.bottom()), QPointF(px, area.bottom() + 5));
    const QString s = tick_text(t);
    p.drawText(QPointF(px - fm.horizontalAdvance(s) / 2, area.bottom() + 8 + fm.ascent()), s);
  }
  for (double t : y.ticks) {
    const double py = map(y, t, area.bottom(), area.top());
    p.drawLine(QPointF(area.left() - 5, py), QPointF(area.left(), py));
    const QString s = tick_text(t);
    p.drawText(QPointF(area.left() - 8 - fm.horizontalAdvance(s), py + fm.ascent() / 2 - 1), s);
  }
  p.drawText(
      QPointF(area.center().x() - fm.horizontalAdvance(x_label) / 2, area.bottom() + 14 + 2 * fm.height()),
      x_label);
  p.translate(area.left() - 60, area.center().y() + fm.horizontalAdvance(y_label) / 2);
  p.rotate(-90);
  p.drawText(QPointF(0, 0), y_label);
  p.restore();
}

void draw_title(QPainter& p, const QRectF& figure, const QString& title) {
  if (title.isEmpty()) return;
  p.save();
  QFont f = p.font();
  f.setBold(true);
  f.setPixelSize(f.pixelSize() * 6 / 5);
  p.setFont(f);
  p.setPen(Qt::black);
  // Two lines at most above a chart that starts 50 px down: a long title wraps, not clips.
  p.drawText(QRectF(figure.left() + 10, figure.top() + 6, figure.width() - 20, 42),
             Qt::AlignHCenter | Qt::AlignTop | Qt::TextWordWrap, title);
  p.restore();
}

}  // namespace detail
}  // namespace tocd::plot

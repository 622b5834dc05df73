#pragma once

#include <QPainter>
#include <QRectF>
#include <QString>
#include <vector>

namespace tocd::plot::detail {

/// A data range mapped onto a pixel span; `ticks` are round numbers inside the range.
struct Axis {
  double lo = 0, hi = 1;
  std::vector<double> ticks;
};

/// An axis over [lo, hi] widened to round tick values (about `target_ticks` of them), so
/// the data never touch the frame. A zero-width range is widened around its value.
Axis nice_axis(double lo, double hi, int target_ticks = 6);

/// Pixel position of `v` on an axis drawn from p0 (lo) to p1 (hi).
inline double map(const Axis& a, double v, double p0, double p1) {
  return p0 + (v - a.lo) / (a.hi - a.lo) * (p1 - p0);
}

/// Frame, ticks, tick labels and axis labels around `area`; x runs left to right, y bottom to top.
void draw_axes(QPainter& p, const QRectF& area, const Axis& x, const Axis& y, const QString& x_label,
               const QString& y_label);

/// The figure title centred above `area`.
void draw_title(QPainter& p, const QRectF& figure, const QString& title);

/// A tick label: up to 4 significant digits, no trailing zeros.
QString tick_text(double v);

}  // namespace tocd::plot::detail

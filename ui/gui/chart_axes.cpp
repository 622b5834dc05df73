#include "chart_axes.hpp"

#include <algorithm>
#include <cmath>

namespace tocd::gui {

std::pair<double, double> padded_range(double lo, double hi, std::pair<double, double> fallback,
                                       double margin_fraction) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || lo > hi) return fallback;
  double span = hi - lo;
  if (span <= 0.0) span = std::max(std::abs(hi) * 0.1, 1e-9);
  return {lo - margin_fraction * span, hi + margin_fraction * span};
}

bool bounds(const std::vector<QPointF>& points, double& x_lo, double& x_hi, double& y_lo, double& y_hi) {
  bool any = false;
  for (const QPointF& p : points) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) continue;
    if (!any) {
      x_lo = x_hi = p.x();
      y_lo = y_hi = p.y();
      any = true;
      continue;
    }
    x_lo = std::min(x_lo, p.x());
    x_hi = std::max(x_hi, p.x());
    y_lo = std::min(y_lo, p.y());
    y_hi = std::max(y_hi, p.y());
  }
  return any;
}

}  // namespace tocd::gui

#pragma once

#include <QPointF>
#include <utility>
#include <vector>

namespace tocd::gui {

/// An axis range [lo, hi] that holds every value with a little margin, never empty
/// (a flat signal still gets a visible band). `fallback` is used when there are no values.
std::pair<double, double> padded_range(double lo, double hi, std::pair<double, double> fallback,
                                       double margin_fraction = 0.05);

/// Min/max of the x and y of `points`; returns false when there are none.
bool bounds(const std::vector<QPointF>& points, double& x_lo, double& x_hi, double& y_lo, double& y_hi);

}  // namespace tocd::gui

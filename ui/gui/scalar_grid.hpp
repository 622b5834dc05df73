#pragma once

#include <QString>
#include <vector>

namespace tocd::gui {

/// A 2-D field sampled on a regular grid (a fluence slice): nx by ny cells covering
/// [x_min, x_max] x [y_min, y_max]; values row-major with row 0 at y_min.
struct ScalarGrid {
  QString title;
  QString x_label = QStringLiteral("x (mm)");
  QString y_label = QStringLiteral("z (mm)");
  int nx = 0, ny = 0;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;
  std::vector<double> values;

  double at(int ix, int iy) const { return values[static_cast<std::size_t>(iy) * nx + ix]; }
  bool empty() const { return nx <= 0 || ny <= 0; }
};

}  // namespace tocd::gui

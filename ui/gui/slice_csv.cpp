#include "slice_csv.hpp"

#include <QFile>
#include <QFileInfo>
#include <QStringList>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

namespace tocd::gui {

namespace {

[[noreturn]] void fail(const QString& source, int line, const QString& what) {
  throw SliceCsvError(QStringLiteral("%1:%2: %3").arg(source).arg(line).arg(what).toStdString());
}

// Distinct coordinate values, merged within a tolerance far below the grid spacing so that
// printing round-off does not split one grid line into two.
std::vector<double> distinct(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (double x : v) {
    if (out.empty() || x - out.back() > 1e-9 * std::max(1.0, std::abs(x))) out.push_back(x);
  }
  return out;
}

int index_of(const std::vector<double>& axis, double x) {
  const auto it = std::lower_bound(axis.begin(), axis.end(), x - 1e-9 * std::max(1.0, std::abs(x)));
  return static_cast<int>(it - axis.begin());
}

// The columns read, in this order: the three coordinates, then the value.
const std::array<QString, 4>& slice_columns() {
  static const std::array<QString, 4> names{QStringLiteral("x_mm"), QStringLiteral("y_mm"),
                                            QStringLiteral("z_mm"), QStringLiteral("fluence")};
  return names;
}

struct SlicePoint {
  std::array<double, 3> xyz;
  double value;
};

// Where each of slice_columns() stands in the header (line 1).
std::array<qsizetype, 4> slice_header(const QStringList& head, const QString& source_name) {
  const auto& wanted = slice_columns();
  std::array<qsizetype, 4> col{};
  for (std::size_t k = 0; k < wanted.size(); ++k) {
    col[k] = head.indexOf(wanted[k]);
    if (col[k] < 0) {
      fail(
          source_name, 1,
          QStringLiteral("header has no column \"%1\" (expected x_mm,y_mm,z_mm,...,fluence)").arg(wanted[k]));
    }
  }
  return col;
}

// One data line (line `line_no` of the file); an empty fluence is a point outside the mesh.
SlicePoint slice_point(const QStringList& cells, const std::array<qsizetype, 4>& col,
                       const QString& source_name, int line_no) {
  SlicePoint p{};
  for (int k = 0; k < 3; ++k) {
    bool ok = false;
    p.xyz[static_cast<std::size_t>(k)] = cells[col[static_cast<std::size_t>(k)]].toDouble(&ok);
    if (!ok)
      fail(source_name, line_no,
           QStringLiteral("%1 is not a number").arg(slice_columns()[static_cast<std::size_t>(k)]));
  }
  const QString f = cells[col[3]].trimmed();
  if (f.isEmpty()) {
    p.value = std::numeric_limits<double>::quiet_NaN();  // outside the mesh
  } else {
    bool ok = false;
    p.value = f.toDouble(&ok);
    if (!ok) fail(source_name, line_no, QStringLiteral("fluence \"%1\" is not a number").arg(f));
  }
  return p;
}

// Every data line after the header; blank lines are skipped.
std::vector<SlicePoint> slice_points(const QStringList& lines, const QString& source_name) {
  const QStringList head = lines[0].trimmed().split(QLatin1Char(','));
  const std::array<qsizetype, 4> col = slice_header(head, source_name);
  std::vector<SlicePoint> points;
  for (int i = 1; i < lines.size(); ++i) {
    const QString line = lines[i].trimmed();
    if (line.isEmpty()) continue;
    const QStringList cells = line.split(QLatin1Char(','));
    if (cells.size() != head.size()) {
      fail(source_name, i + 1,
           QStringLiteral("%1 fields, the header has %2").arg(cells.size()).arg(head.size()));
    }
    points.push_back(slice_point(cells, col, source_name, i + 1));
  }
  if (points.empty()) fail(source_name, 2, QStringLiteral("no data rows"));
  return points;
}

// The distinct values of each coordinate.
std::array<std::vector<double>, 3> slice_axes(const std::vector<SlicePoint>& points) {
  std::array<std::vector<double>, 3> axes;
  for (int k = 0; k < 3; ++k) {
    std::vector<double> v;
    v.reserve(points.size());
    for (const SlicePoint& p : points) v.push_back(p.xyz[static_cast<std::size_t>(k)]);
    axes[static_cast<std::size_t>(k)] = distinct(std::move(v));
  }
  return axes;
}

}  // namespace

ScalarGrid parse_slice_csv(const QString& text, const QString& source_name) {
  const QStringList lines = text.split(QLatin1Char('\n'));
  if (lines.isEmpty() || lines[0].trimmed().isEmpty()) fail(source_name, 1, QStringLiteral("empty file"));
  const std::vector<SlicePoint> points = slice_points(lines, source_name);
  const std::array<std::vector<double>, 3> axes = slice_axes(points);
  // The picture's horizontal axis is the first varying coordinate, its vertical axis the
  // last (x-y at pin-tip height, x-z through the axis).
  std::vector<int> varying;
  for (int k = 0; k < 3; ++k)
    if (axes[static_cast<std::size_t>(k)].size() > 1) varying.push_back(k);
  if (varying.size() != 2) {
    fail(source_name, 2,
         QStringLiteral("points do not lie on a plane grid (%1 coordinates vary)").arg(varying.size()));
  }
  const auto& u = axes[static_cast<std::size_t>(varying[0])];
  const auto& v = axes[static_cast<std::size_t>(varying[1])];
  ScalarGrid g;
  g.nx = static_cast<int>(u.size());
  g.ny = static_cast<int>(v.size());
  if (static_cast<std::size_t>(g.nx) * g.ny != points.size()) {
    fail(source_name, 2,
         QStringLiteral("%1 points do not fill a %2 x %3 grid").arg(points.size()).arg(g.nx).arg(g.ny));
  }
  static const char* const kNames[] = {"x (mm)", "y (mm)", "z (mm)"};
  g.x_label = QString::fromLatin1(kNames[varying[0]]);
  g.y_label = QString::fromLatin1(kNames[varying[1]]);
  // Cells are centred on the sample points: the picture spans half a spacing beyond them.
  const double du = (u.back() - u.front()) / (g.nx - 1);
  const double dv = (v.back() - v.front()) / (g.ny - 1);
  g.x_min = u.front() - du / 2;
  g.x_max = u.back() + du / 2;
  g.y_min = v.front() - dv / 2;
  g.y_max = v.back() + dv / 2;
  g.values.assign(points.size(), std::numeric_limits<double>::quiet_NaN());
  for (const SlicePoint& p : points) {
    const int ix = index_of(u, p.xyz[static_cast<std::size_t>(varying[0])]);
    const int iy = index_of(v, p.xyz[static_cast<std::size_t>(varying[1])]);
    g.values[static_cast<std::size_t>(iy) * g.nx + ix] = p.value;
  }
  g.title = source_name;
  return g;
}

ScalarGrid read_slice_csv(const QString& path) {
  QFile f(path);
  if (!f.open(QIODevice::ReadOnly | QIODevice::Text)) {
    throw SliceCsvError(QStringLiteral("%1: cannot read: %2").arg(path, f.errorString()).toStdString());
  }
  ScalarGrid g = parse_slice_csv(QString::fromUtf8(f.readAll()), path);
  g.title = QFileInfo(path).completeBaseName();
  return g;
}

}  // namespace tocd::gui

#include <QPainterPath>
#include <algorithm>
#include <cmath>
#include <limits>

#include "axes.hpp"
#include "canvas.hpp"
#include "legend.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/figures.hpp"

namespace tocd::plot {

void write_figure(const FitFigure& figure, const std::filesystem::path& path, FigureSize size) {
  if (figure.strain.empty() || figure.strain.size() != figure.stress_MPa.size())
    throw ConfigError("fit figure: the data need as many stresses as strains, at least one");
  if (figure.curve_strain.size() != figure.curve_stress_MPa.size())
    throw ConfigError("fit figure: the fitted curve needs as many stresses as strains");
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  auto extend = [&](const std::vector<double>& xs, const std::vector<double>& ys) {
    for (std::size_t k = 0; k < xs.size(); ++k) {
      if (!std::isfinite(xs[k]) || !std::isfinite(ys[k])) continue;
      x_lo = std::min(x_lo, xs[k]), x_hi = std::max(x_hi, xs[k]);
      y_lo = std::min(y_lo, ys[k]), y_hi = std::max(y_hi, ys[k]);
    }
  };
  extend(figure.strain, figure.stress_MPa);
  extend(figure.curve_strain, figure.curve_stress_MPa);
  if (!std::isfinite(x_lo)) throw ConfigError("fit figure: no finite stress-strain point");
  const auto x = detail::nice_axis(std::min(0.0, x_lo), x_hi);
  const auto y = detail::nice_axis(std::min(0.0, y_lo), y_hi);
  const QRectF area = detail::qrect(chart_area(size));
  const QColor data_colour = detail::qcolour(kMeasuredColour),
               curve_colour = detail::qcolour(kPredictedColour);
  auto data_glyph = [&](QPainter& p, QPointF c) {
    p.setPen(QPen(Qt::black, 0.6));
    p.setBrush(data_colour);
    p.drawEllipse(c, 3.5, 3.5);
  };
  auto curve_glyph = [&](QPainter& p, QPointF c) {
    p.setPen(QPen(curve_colour, 2.5));
    p.drawLine(QPointF(c.x() - 9, c.y()), QPointF(c.x() + 9, c.y()));
  };
  detail::render_to_file(path, size, [&](QPainter& p) {
    detail::draw_title(p, QRectF(0, 0, size.width, size.height), QString::fromStdString(figure.title));
    detail::draw_axes(p, area, x, y, QStringLiteral("nominal strain"),
                      QStringLiteral("nominal stress (MPa)"));
    auto at = [&](double sx, double sy) {
      return QPointF(detail::map(x, sx, area.left(), area.right()),
                     detail::map(y, sy, area.bottom(), area.top()));
    };
    for (std::size_t k = 0; k < figure.strain.size(); ++k)
      if (std::isfinite(figure.strain[k]) && std::isfinite(figure.stress_MPa[k]))
        data_glyph(p, at(figure.strain[k], figure.stress_MPa[k]));
    QPainterPath curve;
    bool pen_down = false;
    for (std::size_t k = 0; k < figure.curve_strain.size(); ++k) {
      if (!std::isfinite(figure.curve_strain[k]) || !std::isfinite(figure.curve_stress_MPa[k])) {
        pen_down = false;
        continue;
      }
      const QPointF q = at(figure.curve_strain[k], figure.curve_stress_MPa[k]);
      pen_down ? curve.lineTo(q) : curve.moveTo(q);
      pen_down = true;
    }
    p.save();
    p.setClipRect(area);
    p.setPen(QPen(curve_colour, 2.5));
    p.setBrush(Qt::NoBrush);
    p.drawPath(curve);
    p.restore();
    std::vector<detail::LegendEntry> legend{{QStringLiteral("data"), data_glyph}};
    if (!figure.curve_strain.empty())
      legend.push_back(
          {QString::fromStdString(figure.curve_label.empty() ? "fit" : figure.curve_label), curve_glyph});
    detail::draw_legend(p, area, legend);
  });
}

}  // namespace tocd::plot

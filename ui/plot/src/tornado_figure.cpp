#include <QFontMetricsF>
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "axes.hpp"
#include "canvas.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/figures.hpp"

namespace tocd::plot {
namespace {

constexpr double kKeySwatch = 14;  // the key's colour squares

void check(const TornadoFigure& figure) {
  const std::size_t n = figure.values.size();
  if (n == 0) throw ConfigError("tornado chart: no bars to draw");
  if (figure.labels.size() != n || figure.errors.size() != n)
    throw ConfigError("tornado chart: labels, values and errors differ in number");
  for (std::size_t k = 0; k < n; ++k)
    if (!std::isfinite(figure.values[k]))
      throw ConfigError("tornado chart: the value of '" + figure.labels[k] + "' is not a number");
}

detail::Axis value_axis(const TornadoFigure& figure) {
  double lo = 0, hi = 0;  // bars grow from zero
  for (std::size_t k = 0; k < figure.values.size(); ++k) {
    const double e = std::isfinite(figure.errors[k]) ? figure.errors[k] : 0.0;
    lo = std::min(lo, figure.values[k] - e), hi = std::max(hi, figure.values[k] + e);
  }
  return detail::nice_axis(lo, hi);
}

}  // namespace

TornadoLayout tornado_layout(const TornadoFigure& figure, FigureSize size) {
  check(figure);
  const std::size_t n = figure.values.size();
  const auto x = value_axis(figure);
  const QFontMetricsF fm(detail::figure_font());
  // The labels sit left of the bars: the chart area starts after the widest of them. Below
  // the x axis' label a line is kept for the key.
  double label_width = 0;
  for (const auto& l : figure.labels)
    label_width = std::max(label_width, fm.horizontalAdvance(QString::fromStdString(l)));
  const PixelRect base = chart_area(size);
  const double left = std::min(label_width + 16, 0.5 * size.width);
  const double r = figure.resolution;
  TornadoLayout out;
  out.key = {fmt::format("|dT| > {:g} s.e.: beyond the Monte Carlo error", r),
             fmt::format("|dT| \u2264 {:g} s.e.: within the Monte Carlo error", r)};
  // The key's entries side by side below the x axis' label, or one above the other when the
  // figure is too narrow for both on one line.
  std::vector<double> widths;
  for (const auto& k : out.key)
    widths.push_back(kKeySwatch + 6 + fm.horizontalAdvance(QString::fromStdString(k)));
  const double line = fm.height() + 4, gap = 24;
  const bool one_line = widths[0] + gap + widths[1] <= size.width - 16.0;
  const double key_height = one_line ? line : 2 * line;
  const double key_top = size.height - key_height - 6;
  double at = one_line ? (size.width - widths[0] - gap - widths[1]) / 2 : 8.0;
  for (std::size_t k = 0; k < out.key.size(); ++k) {
    out.key_boxes.push_back(
        {at, key_top + (one_line ? 0.0 : static_cast<double>(k) * line), widths[k], fm.height()});
    if (one_line) at += widths[k] + gap;
  }
  out.area = {left, base.y, size.width - left - 30, base.height - key_height};
  auto px = [&](double v) { return detail::map(x, v, out.area.x, out.area.x + out.area.width); };
  const double slot = out.area.height / static_cast<double>(n), thick = 0.7 * slot;
  for (std::size_t k = 0; k < n; ++k) {
    const double cy = out.area.y + (static_cast<double>(k) + 0.5) * slot;
    const double v = figure.values[k], e = figure.errors[k];
    out.resolved.push_back(std::isfinite(e) && std::abs(v) > r * e);
    const double a = px(std::min(v, 0.0)), b = px(std::max(v, 0.0));
    out.bars.push_back({a, cy - thick / 2, b - a, thick});
  }
  return out;
}

void write_figure(const TornadoFigure& figure, const std::filesystem::path& path, FigureSize size) {
  const TornadoLayout layout = tornado_layout(figure, size);
  const auto x = value_axis(figure);
  const QRectF area = detail::qrect(layout.area);
  detail::render_to_file(path, size, [&](QPainter& p) {
    const QFontMetricsF fm(p.font());
    detail::draw_title(p, QRectF(0, 0, size.width, size.height), QString::fromStdString(figure.title));
    detail::draw_axes(p, area, x, detail::Axis{0, 1, {}}, QString::fromStdString(figure.x_label), QString());
    auto px = [&](double v) { return detail::map(x, v, area.left(), area.right()); };
    const double slot = area.height() / static_cast<double>(layout.bars.size());
    for (std::size_t k = 0; k < layout.bars.size(); ++k) {
      const QRectF bar = detail::qrect(layout.bars[k]);
      const double cy = bar.center().y();
      const double v = figure.values[k], e = figure.errors[k];
      p.fillRect(bar, detail::qcolour(layout.resolved[k] ? kMeasuredColour : kUnresolvedColour));
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
    // The key: what dark and pale bars mean.
    const Rgb colours[2] = {kMeasuredColour, kUnresolvedColour};
    for (std::size_t k = 0; k < layout.key.size(); ++k) {
      const QRectF box = detail::qrect(layout.key_boxes[k]);
      p.fillRect(QRectF(box.left(), box.center().y() - kKeySwatch / 2, kKeySwatch, kKeySwatch),
                 detail::qcolour(colours[k]));
      p.setPen(Qt::black);
      p.drawText(QPointF(box.left() + kKeySwatch + 6, box.top() + fm.ascent()),
                 QString::fromStdString(layout.key[k]));
    }
  });
}

}  // namespace tocd::plot

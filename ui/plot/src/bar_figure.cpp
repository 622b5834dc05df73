#include <QFontMetricsF>
#include <QStringList>
#include <algorithm>
#include <cmath>
#include <limits>

#include "axes.hpp"
#include "canvas.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/figures.hpp"

namespace tocd::plot {
namespace {

constexpr double kLabelGap = 6;  // between the axis and the labels, and around the slot's text

void check(const BarFigure& figure) {
  const std::size_t n = figure.values.size();
  if (n == 0) throw ConfigError("bar chart: no bars to draw");
  if (figure.labels.size() != n || (!figure.errors.empty() && figure.errors.size() != n))
    throw ConfigError("bar chart: labels, values and errors differ in number");
  for (std::size_t k = 0; k < n; ++k)
    if (!std::isfinite(figure.values[k]))
      throw ConfigError("bar chart: the value of '" + figure.labels[k] + "' is not a number");
}

double error_of(const BarFigure& f, std::size_t k) {
  return f.errors.empty() || !std::isfinite(f.errors[k]) || f.errors[k] <= 0
             ? std::numeric_limits<double>::quiet_NaN()
             : f.errors[k];
}

// Greedy word wrap of each '\n'-separated part into lines no wider than `width`. Returns false
// when one word alone is wider: such a label cannot stand upright in its slot.
bool wrap(const QString& label, const QFontMetricsF& fm, double width, QStringList& lines) {
  lines.clear();
  for (const QString& part : label.split('\n')) {
    QString line;
    // A number and its unit (joined by a no-break space) stay on one line when they fit it.
    QStringList words;
    for (const QString& word : part.split(' ', Qt::SkipEmptyParts))
      words << (fm.horizontalAdvance(word) > width ? word.split(QChar(0x00a0), Qt::SkipEmptyParts)
                                                   : QStringList{word});
    for (const QString& word : words) {
      if (fm.horizontalAdvance(word) > width) return false;
      const QString longer = line.isEmpty() ? word : line + ' ' + word;
      if (fm.horizontalAdvance(longer) <= width) {
        line = longer;
      } else {
        lines << line;
        line = word;
      }
    }
    lines << line;
  }
  return true;
}

}  // namespace

BarLayout bar_layout(const BarFigure& figure, FigureSize size) {
  check(figure);
  const std::size_t n = figure.values.size();
  double lo = 0, hi = 0;  // bars grow from zero
  for (std::size_t k = 0; k < n; ++k) {
    const double e = std::isfinite(error_of(figure, k)) ? error_of(figure, k) : 0.0;
    lo = std::min(lo, figure.values[k] - e), hi = std::max(hi, figure.values[k] + e);
  }
  const auto y = detail::nice_axis(lo, hi);
  const QFontMetricsF fm(detail::figure_font());
  BarLayout out;
  out.y_lo = y.lo, out.y_hi = y.hi;
  out.line_height = fm.height();
  const PixelRect base = chart_area(size);
  const double slot = base.width / static_cast<double>(n), room = slot - kLabelGap;
  // Upright and wrapped when every word fits its slot, else upright text would run into the
  // neighbours' labels: then every label is turned to read bottom to top, one line per part.
  std::vector<QStringList> lines(n);
  bool upright = true;
  for (std::size_t k = 0; k < n && upright; ++k)
    upright = wrap(QString::fromStdString(figure.labels[k]), fm, room, lines[k]);
  out.labels_rotated = !upright;
  // The bottom margin holds the tallest label, the x axis' label and a gap.
  const double max_margin = 0.5 * size.height;
  const double x_label_room = figure.x_label.empty() ? 0.0 : out.line_height + kLabelGap;
  double label_room = max_margin - 2 * kLabelGap - x_label_room;
  std::vector<double> extent(n, 0.0);  // each label's length down from the axis
  for (std::size_t k = 0; k < n; ++k) {
    if (upright) {
      extent[k] = static_cast<double>(lines[k].size()) * out.line_height;
      continue;
    }
    lines[k] = QString::fromStdString(figure.labels[k]).split('\n');
    // Columns of turned text side by side; when they do not fit the slot, one column.
    if (static_cast<double>(lines[k].size()) * out.line_height > room)
      lines[k] = QStringList{lines[k].join(", ")};
    for (QString& l : lines[k]) {
      l = fm.elidedText(l, Qt::ElideRight, label_room);
      extent[k] = std::max(extent[k], fm.horizontalAdvance(l));
    }
  }
  label_room = *std::max_element(extent.begin(), extent.end());
  const double bottom = std::max(70.0, kLabelGap + label_room + kLabelGap + x_label_room + kLabelGap);
  out.area = {base.x, base.y, base.width, size.height - base.y - bottom};
  auto py = [&](double v) { return detail::map(y, v, out.area.y + out.area.height, out.area.y); };
  const double width = 0.7 * slot, label_top = out.area.y + out.area.height + kLabelGap;
  for (std::size_t k = 0; k < n; ++k) {
    const double cx = out.area.x + (static_cast<double>(k) + 0.5) * slot;
    const double v = figure.values[k], e = error_of(figure, k);
    const double top = py(std::max(v, 0.0)), foot = py(std::min(v, 0.0));
    out.bars.push_back({cx - width / 2, top, width, foot - top});
    out.error_low_y.push_back(std::isfinite(e) ? py(v - e) : e);
    out.error_high_y.push_back(std::isfinite(e) ? py(v + e) : e);
    std::vector<std::string> text;
    double text_width = 0;
    for (const QString& l : lines[k]) {
      text.push_back(l.toStdString());
      text_width = std::max(text_width, fm.horizontalAdvance(l));
    }
    const double across = upright ? text_width : static_cast<double>(lines[k].size()) * out.line_height;
    out.label_boxes.push_back({cx - across / 2, label_top, across, extent[k]});
    out.label_lines.push_back(std::move(text));
  }
  return out;
}

void write_figure(const BarFigure& figure, const std::filesystem::path& path, FigureSize size) {
  const BarLayout layout = bar_layout(figure, size);
  const QRectF area = detail::qrect(layout.area);
  const detail::Axis y = detail::nice_axis(layout.y_lo, layout.y_hi);
  detail::render_to_file(path, size, [&](QPainter& p) {
    detail::draw_title(p, QRectF(0, 0, size.width, size.height), QString::fromStdString(figure.title));
    detail::draw_axes(p, area, detail::Axis{0, 1, {}}, y, QString(), QString::fromStdString(figure.y_label));
    const QFontMetricsF fm(p.font());
    for (std::size_t k = 0; k < layout.bars.size(); ++k) {
      const QRectF bar = detail::qrect(layout.bars[k]);
      p.fillRect(bar, detail::qcolour(kMeasuredColour));
      const double cx = bar.center().x();
      if (std::isfinite(layout.error_low_y[k])) {
        const double y0 = layout.error_low_y[k], y1 = layout.error_high_y[k];
        p.setPen(QPen(Qt::black, 1.2));
        p.drawLine(QPointF(cx, y0), QPointF(cx, y1));
        p.drawLine(QPointF(cx - 5, y0), QPointF(cx + 5, y0));
        p.drawLine(QPointF(cx - 5, y1), QPointF(cx + 5, y1));
      }
      p.setPen(Qt::black);
      const QRectF box = detail::qrect(layout.label_boxes[k]);
      const auto& lines = layout.label_lines[k];
      for (std::size_t i = 0; i < lines.size(); ++i) {
        const QString s = QString::fromStdString(lines[i]);
        const double w = fm.horizontalAdvance(s);
        if (!layout.labels_rotated) {
          p.drawText(
              QPointF(cx - w / 2, box.top() + static_cast<double>(i) * layout.line_height + fm.ascent()), s);
          continue;
        }
        // Turned a quarter to the left: the text reads upward and ends at the axis.
        const double column = box.left() + (static_cast<double>(i) + 0.5) * layout.line_height;
        p.save();
        p.translate(column + (fm.ascent() - fm.descent()) / 2, box.top() + w);
        p.rotate(-90);
        p.drawText(QPointF(0, 0), s);
        p.restore();
      }
    }
    if (!figure.x_label.empty()) {
      double bottom = 0;
      for (const auto& b : layout.label_boxes) bottom = std::max(bottom, b.y + b.height);
      const QString s = QString::fromStdString(figure.x_label);
      p.drawText(QPointF(area.center().x() - fm.horizontalAdvance(s) / 2, bottom + kLabelGap + fm.ascent()),
                 s);
    }
    if (layout.y_lo < 0) {  // the zero line, when bars go both ways
      const double zero = detail::map(y, 0.0, area.bottom(), area.top());
      p.setPen(QPen(Qt::black, 1.0));
      p.drawLine(QPointF(area.left(), zero), QPointF(area.right(), zero));
    }
  });
}

}  // namespace tocd::plot

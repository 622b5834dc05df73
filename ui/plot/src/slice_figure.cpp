#include <QFontMetricsF>
#include <QImage>
#include <QPainterPath>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "axes.hpp"
#include "canvas.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/figures.hpp"

namespace tocd::plot {
namespace {

void check(const SliceFigure& f) {
  if (f.panels.empty()) throw ConfigError("slice figure: no slices to draw");
  if (!(f.decades > 0 && f.decades <= 30))
    throw ConfigError("slice figure: the colour scale's decades must be above 0 and at most 30");
  for (const auto& s : f.panels) {
    const auto cells =
        static_cast<std::size_t>(std::max(0, s.nx)) * static_cast<std::size_t>(std::max(0, s.ny));
    if (s.nx < 2 || s.ny < 2 || s.fluence.size() != cells || s.region.size() != cells ||
        !(s.x_max > s.x_min) || !(s.y_max > s.y_min))
      throw ConfigError("slice '" + s.title + "': not a regular grid of at least 2 x 2 points");
  }
}

bool inside_mesh(double fluence, int region) {
  return std::isfinite(fluence) && region != 0;
}

// A colour bar's end label: the value, with ">=" or "<=" where cells beyond it share its colour.
std::string end_label(const char* sign, double log10_v, bool clipped) {
  return (clipped ? std::string(sign) + " " : std::string()) + fmt::format("{:.2g}", std::pow(10.0, log10_v));
}

// The colour scale of the layout: its top is the area-weighted `top_quantile` of the fluence
// over the cells inside the mesh (cells of one panel are equal in area: the grid is regular),
// its bottom `decades` below (or the smallest positive fluence, when that is higher).
void colour_scale(const SliceFigure& f, SliceLayout& out) {
  std::vector<std::pair<double, double>> cells;  // fluence, area
  double min_positive = std::numeric_limits<double>::infinity(), max_positive = 0;
  for (const auto& s : f.panels) {
    const double area = (s.x_max - s.x_min) / s.nx * (s.y_max - s.y_min) / s.ny;
    for (std::size_t k = 0; k < s.fluence.size(); ++k) {
      const double v = s.fluence[k];
      if (!inside_mesh(v, s.region[k])) {
        out.has_outside = true;
        continue;
      }
      cells.emplace_back(std::max(v, 0.0), area);
      if (v > 0) min_positive = std::min(min_positive, v), max_positive = std::max(max_positive, v);
    }
  }
  if (!(max_positive > 0)) throw ConfigError("slice figure: no slice has a positive fluence to draw");
  std::sort(cells.begin(), cells.end());
  double total = 0;
  for (const auto& c : cells) total += c.second;
  double top = max_positive, below = 0;
  for (const auto& c : cells) {
    below += c.second;
    if (below >= f.top_quantile * total) {
      top = c.first;
      break;
    }
  }
  if (!(top > 0)) top = max_positive;  // most of the area dark: the scale still needs a top
  double hi = std::log10(top), lo = std::max(std::log10(min_positive), hi - f.decades);
  if (hi - lo < 1e-9) lo = hi - 1.0;  // a uniform field: one decade so the bar still reads
  out.log10_min = lo, out.log10_max = hi;
  out.clipped_high = max_positive > top * (1 + 1e-12);
  out.clipped_low = false;
  for (const auto& c : cells) out.clipped_low = out.clipped_low || c.first < std::pow(10.0, lo) * (1 - 1e-12);
  out.top_label = end_label("\u2265", hi, out.clipped_high);
  out.bottom_label = end_label("\u2264", lo, out.clipped_low);
}

}  // namespace

SliceLayout slice_layout(const SliceFigure& figure, FigureSize size) {
  check(figure);
  if (!(figure.top_quantile > 0 && figure.top_quantile <= 1))
    throw ConfigError("slice figure: the colour scale's top quantile must be above 0 and at most 1");
  SliceLayout out;
  colour_scale(figure, out);
  for (const auto& s : figure.panels) out.panel_titles.push_back(s.title);
  // Panels share the width left of the colour bar; each keeps its true aspect ratio (1 mm
  // is as long across as up), centred in its slot.
  const double top = 60, bottom = 70, left = 80, bar_room = 130, gap = 80;
  const auto n = static_cast<double>(figure.panels.size());
  const double slot_w = (size.width - left - bar_room - (n - 1) * gap) / n;
  const double slot_h = size.height - top - bottom;
  for (std::size_t k = 0; k < figure.panels.size(); ++k) {
    const auto& s = figure.panels[k];
    const double aspect = (s.y_max - s.y_min) / (s.x_max - s.x_min);
    double w = slot_w, h = slot_w * aspect;
    if (h > slot_h) h = slot_h, w = slot_h / aspect;
    const double slot_x = left + static_cast<double>(k) * (slot_w + gap);
    out.panels.push_back({slot_x + (slot_w - w) / 2, top + (slot_h - h) / 2, w, h});
  }
  // Room below the bar for the outside-the-mesh swatch, when there is one.
  out.colour_bar = {size.width - bar_room + 30, top, 22, slot_h - (out.has_outside ? 40.0 : 0.0)};
  return out;
}

Rgb slice_cell_colour(double fluence, int region, const SliceLayout& layout) {
  if (!inside_mesh(fluence, region)) return kNoDataColour;
  // No photon reached the cell: the darkest colour, as every value at or below the bottom.
  if (!(fluence > 0)) return fluence_ramp(0.0);
  return fluence_ramp((std::log10(fluence) - layout.log10_min) / (layout.log10_max - layout.log10_min));
}

void write_figure(const SliceFigure& figure, const std::filesystem::path& path, FigureSize size) {
  const SliceLayout layout = slice_layout(figure, size);
  const double lo = layout.log10_min, hi = layout.log10_max;
  detail::render_to_file(path, size, [&](QPainter& p) {
    detail::draw_title(p, QRectF(0, 0, size.width, size.height), QString::fromStdString(figure.title));
    for (std::size_t k = 0; k < figure.panels.size(); ++k) {
      const auto& s = figure.panels[k];
      const QRectF area = detail::qrect(layout.panels[k]);
      QImage cells(s.nx, s.ny, QImage::Format_RGB32);
      for (int j = 0; j < s.ny; ++j)
        for (int i = 0; i < s.nx; ++i)
          cells.setPixelColor(
              i, s.ny - 1 - j,
              detail::qcolour(slice_cell_colour(s.fluence[j * s.nx + i], s.region[j * s.nx + i], layout)));
      p.save();
      p.setRenderHint(QPainter::SmoothPixmapTransform, false);
      p.drawImage(area, cells);
      // Region outlines: a segment wherever two neighbouring cells belong to different regions.
      const double cw = area.width() / s.nx, ch = area.height() / s.ny;
      QPainterPath outline;
      auto region = [&](int i, int j) { return s.region[static_cast<std::size_t>(j) * s.nx + i]; };
      for (int j = 0; j < s.ny; ++j)
        for (int i = 0; i < s.nx; ++i) {
          const double x = area.left() + i * cw, y = area.bottom() - (j + 1) * ch;
          if (i + 1 < s.nx && region(i, j) != region(i + 1, j)) {
            outline.moveTo(x + cw, y);
            outline.lineTo(x + cw, y + ch);
          }
          if (j + 1 < s.ny && region(i, j) != region(i, j + 1)) {
            outline.moveTo(x, y);
            outline.lineTo(x + cw, y);
          }
        }
      p.setPen(QPen(detail::qcolour(kRegionOutlineColour), 1.0));
      p.setBrush(Qt::NoBrush);
      p.drawPath(outline);
      p.restore();
      const auto x_axis = detail::Axis{s.x_min, s.x_max, detail::nice_axis(s.x_min, s.x_max, 5).ticks};
      const auto y_axis = detail::Axis{s.y_min, s.y_max, detail::nice_axis(s.y_min, s.y_max, 5).ticks};
      auto inside = [](const detail::Axis& a) {
        detail::Axis b = a;
        std::erase_if(b.ticks, [&](double t) { return t < a.lo - 1e-9 || t > a.hi + 1e-9; });
        return b;
      };
      detail::draw_axes(p, area, inside(x_axis), inside(y_axis), QString::fromStdString(s.x_label),
                        QString::fromStdString(s.y_label));
      p.setPen(Qt::black);
      p.drawText(QRectF(area.left(), area.top() - 22, area.width(), 20), Qt::AlignHCenter | Qt::AlignBottom,
                 QString::fromStdString(s.title));
    }
    // Colour bar: the ramp bottom (low) to top (high), a tick per decade.
    const QRectF bar = detail::qrect(layout.colour_bar);
    QImage ramp(1, 256, QImage::Format_RGB32);
    for (int r = 0; r < 256; ++r) ramp.setPixelColor(0, 255 - r, detail::qcolour(fluence_ramp(r / 255.0)));
    p.save();
    p.setRenderHint(QPainter::SmoothPixmapTransform, false);
    p.drawImage(bar, ramp);
    p.restore();
    p.setPen(Qt::black);
    p.setBrush(Qt::NoBrush);
    p.drawRect(bar);
    const QFontMetricsF fm(p.font());
    auto tick = [&](double y, const QString& text) {
      p.drawLine(QPointF(bar.right(), y), QPointF(bar.right() + 5, y));
      p.drawText(QPointF(bar.right() + 8, y + fm.ascent() / 2 - 1), text);
    };
    // A tick per decade, except where it would run into the end labels.
    for (double d = std::ceil(lo); d <= hi + 1e-9; d += 1.0) {
      const double y = bar.bottom() - (d - lo) / (hi - lo) * bar.height();
      if (y - bar.top() > fm.height() && bar.bottom() - y > fm.height())
        tick(y, QStringLiteral("1e%1").arg(d, 0, 'f', 0));
    }
    tick(bar.top(), QString::fromStdString(layout.top_label));
    tick(bar.bottom(), QString::fromStdString(layout.bottom_label));
    if (layout.has_outside) {
      const QRectF swatch(bar.left(), bar.bottom() + 18, bar.width(), 14);
      p.fillRect(swatch, detail::qcolour(kNoDataColour));
      p.drawRect(swatch);
      p.drawText(QPointF(swatch.left() - 10, swatch.bottom() + 4 + fm.ascent()),
                 QStringLiteral("outside the mesh"));
    }
    p.save();
    p.translate(bar.right() + 62, bar.center().y() + 80);
    p.rotate(-90);
    p.drawText(QPointF(0, 0), QStringLiteral("fluence (mm\u207b\u00b2 per photon)"));
    p.restore();
  });
}

}  // namespace tocd::plot

#include <QFontMetricsF>
#include <QImage>
#include <QPainterPath>
#include <algorithm>
#include <cmath>
#include <limits>

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

// log10 of the largest positive fluence of every panel, and `decades` below it (or the
// smallest positive fluence, when that is higher).
std::pair<double, double> log_range(const SliceFigure& f) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& s : f.panels)
    for (double v : s.fluence)
      if (v > 0 && std::isfinite(v)) lo = std::min(lo, std::log10(v)), hi = std::max(hi, std::log10(v));
  if (!std::isfinite(hi)) throw ConfigError("slice figure: no slice has a positive fluence to draw");
  lo = std::max(lo, hi - f.decades);
  if (hi - lo < 1e-9) lo = hi - 1.0;  // a uniform field: one decade so the bar still reads
  return {lo, hi};
}

Rgb colour_of(double v, double lo, double hi) {
  if (!(v > 0) || !std::isfinite(v)) return kNoDataColour;
  return fluence_ramp((std::log10(v) - lo) / (hi - lo));
}

}  // namespace

SliceLayout slice_layout(const SliceFigure& figure, FigureSize size) {
  check(figure);
  SliceLayout out;
  std::tie(out.log10_min, out.log10_max) = log_range(figure);
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
  out.colour_bar = {size.width - bar_room + 30, top, 22, slot_h};
  return out;
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
          cells.setPixelColor(i, s.ny - 1 - j, detail::qcolour(colour_of(s.fluence[j * s.nx + i], lo, hi)));
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
    for (double d = std::ceil(lo); d <= hi + 1e-9; d += 1.0) {
      const double y = bar.bottom() - (d - lo) / (hi - lo) * bar.height();
      p.drawLine(QPointF(bar.right(), y), QPointF(bar.right() + 5, y));
      p.drawText(QPointF(bar.right() + 8, y + fm.ascent() / 2 - 1), QStringLiteral("1e%1").arg(d, 0, 'f', 0));
    }
    p.save();
    p.translate(bar.right() + 62, bar.center().y() + 80);
    p.rotate(-90);
    p.drawText(QPointF(0, 0), QStringLiteral("fluence (mm\u207b\u00b2 per photon)"));
    p.restore();
  });
}

}  // namespace tocd::plot

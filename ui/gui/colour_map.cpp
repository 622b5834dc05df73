#include "colour_map.hpp"

#include <QPainter>
#include <algorithm>
#include <cmath>
#include <limits>

#include "tocd/plot/figures.hpp"

namespace tocd::gui {

FluenceMapPair::FluenceMapPair(QWidget* parent) : QWidget(parent) {
  setMinimumSize(420, 220);
}

// The figures' ramp (tocdlab plot): a map on screen and its picture share their colours.
QColor FluenceMapPair::ramp(double t) {
  const tocd::plot::Rgb c = tocd::plot::fluence_ramp(t);
  return {c.r, c.g, c.b};
}

void FluenceMapPair::set_dynamic_range_decades(double decades) {
  decades_ = std::max(decades, 0.1);
  update_range();
  for (std::size_t k = 0; k < 2; ++k) images_[k] = render(grids_[k]);
  update();
}

void FluenceMapPair::set_maps(ScalarGrid left, ScalarGrid right) {
  grids_[0] = std::move(left);
  grids_[1] = std::move(right);
  update_range();
  for (std::size_t k = 0; k < 2; ++k) images_[k] = render(grids_[k]);
  update();
}

void FluenceMapPair::clear() {
  set_maps({}, {});
}

void FluenceMapPair::update_range() {
  double lo = std::numeric_limits<double>::infinity();
  double hi = 0.0;
  for (const ScalarGrid& g : grids_) {
    for (double v : g.values) {
      if (!(v > 0.0) || !std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!(hi > 0.0)) {
    range_ = {0.0, 0.0};
    return;
  }
  const double top = std::log10(hi);
  // Monte Carlo tallies reach down to single-photon noise far from the beam; a fixed
  // number of decades keeps that noise from flattening the interesting part of the map.
  const double bottom = std::max(std::log10(lo), top - decades_);
  range_ = {bottom, top};
}

QColor FluenceMapPair::colour_of(double value) const {
  if (!(value > 0.0) || !std::isfinite(value)) return no_data_colour();
  const double span = range_.second - range_.first;
  if (span <= 0.0) return ramp(1.0);  // a uniform field: every cell is the maximum
  return ramp((std::log10(value) - range_.first) / span);
}

QImage FluenceMapPair::render(const ScalarGrid& g) const {
  if (g.empty()) return {};
  QImage img(g.nx, g.ny, QImage::Format_RGB32);
  for (int iy = 0; iy < g.ny; ++iy) {
    // Row 0 of the grid is at y_min, which is the bottom of the picture.
    auto* line = reinterpret_cast<QRgb*>(img.scanLine(g.ny - 1 - iy));
    for (int ix = 0; ix < g.nx; ++ix) line[ix] = colour_of(g.at(ix, iy)).rgb();
  }
  return img;
}

void FluenceMapPair::paintEvent(QPaintEvent* /*event*/) {
  QPainter p(this);
  p.fillRect(rect(), palette().window());
  const int bar_w = 70;
  const int gap = 12;
  const int title_h = fontMetrics().height() + 4;
  const int label_h = fontMetrics().height() + 4;
  const int panel_w = std::max(10, (width() - bar_w - 3 * gap) / 2);
  const int panel_h = std::max(10, height() - title_h - 2 * label_h - gap);

  for (int k = 0; k < 2; ++k) {
    const ScalarGrid& g = grids_[static_cast<std::size_t>(k)];
    const QRect frame(gap + k * (panel_w + gap), title_h, panel_w, panel_h);
    p.setPen(palette().windowText().color());
    p.drawText(QRect(frame.left(), 0, frame.width(), title_h), Qt::AlignCenter,
               g.empty() ? tr("(no slice)") : g.title);
    if (g.empty()) {
      p.drawRect(frame);
      continue;
    }
    // Keep the physical aspect ratio: a millimetre is as wide as it is tall.
    const double w_mm = std::max(g.x_max - g.x_min, 1e-9);
    const double h_mm = std::max(g.y_max - g.y_min, 1e-9);
    const double scale = std::min(frame.width() / w_mm, frame.height() / h_mm);
    const QSize size(std::max(1, static_cast<int>(w_mm * scale)),
                     std::max(1, static_cast<int>(h_mm * scale)));
    const QRect target(frame.left() + (frame.width() - size.width()) / 2, frame.top(), size.width(),
                       size.height());
    p.drawImage(target, images_[static_cast<std::size_t>(k)]);
    p.drawRect(target.adjusted(0, 0, -1, -1));
    const QRect labels(target.left(), target.bottom() + 2, target.width(), label_h);
    p.drawText(labels, Qt::AlignLeft, QString::number(g.x_min, 'g', 3));
    p.drawText(labels, Qt::AlignHCenter, g.x_label);
    p.drawText(labels, Qt::AlignRight, QString::number(g.x_max, 'g', 3));
    const QRect ylabels(target.left(), target.bottom() + 2 + label_h, target.width(), label_h);
    p.drawText(ylabels, Qt::AlignHCenter,
               QStringLiteral("%1: %2 .. %3").arg(g.y_label).arg(g.y_min, 0, 'g', 3).arg(g.y_max, 0, 'g', 3));
  }

  // The shared colour bar, with a tick per decade.
  const QRect bar(width() - bar_w + 4, title_h, 16, panel_h);
  for (int y = 0; y < bar.height(); ++y) {
    const double t = 1.0 - static_cast<double>(y) / std::max(1, bar.height() - 1);
    p.setPen(ramp(t));
    p.drawLine(bar.left(), bar.top() + y, bar.right(), bar.top() + y);
  }
  p.setPen(palette().windowText().color());
  p.drawRect(bar.adjusted(0, 0, -1, -1));
  p.drawText(QRect(bar.left() - 10, 0, bar_w, title_h), Qt::AlignCenter, tr("fluence"));
  const auto [lo, hi] = range_;
  if (hi > lo) {
    for (int e = static_cast<int>(std::ceil(lo)); e <= static_cast<int>(std::floor(hi)); ++e) {
      const int y = bar.bottom() - static_cast<int>((e - lo) / (hi - lo) * (bar.height() - 1));
      p.drawLine(bar.right(), y, bar.right() + 4, y);
      p.drawText(bar.right() + 6, y + fontMetrics().ascent() / 2, QStringLiteral("1e%1").arg(e));
    }
  }
}

}  // namespace tocd::gui

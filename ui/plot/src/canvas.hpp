#pragma once

#include <QColor>
#include <QPainter>
#include <QRectF>
#include <filesystem>
#include <functional>

#include "tocd/plot/figures.hpp"

namespace tocd::plot::detail {

/// Paints a figure of `size` with `paint` (white background already filled) into `path`, as
/// PNG (QImage) or SVG (QSvgGenerator) by extension, on Qt's offscreen platform: no display is
/// ever needed. The file appears complete or not at all.
void render_to_file(const std::filesystem::path& path, FigureSize size,
                    const std::function<void(QPainter&)>& paint);

inline QColor qcolour(Rgb c) {
  return QColor(c.r, c.g, c.b);
}
inline QRectF qrect(const PixelRect& r) {
  return QRectF(r.x, r.y, r.width, r.height);
}

}  // namespace tocd::plot::detail

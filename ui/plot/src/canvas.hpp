#pragma once

#include <QColor>
#include <QFont>
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

/// Starts Qt's offscreen GUI application once (text needs its font database). Layouts that
/// measure text call it before rendering does.
void ensure_gui_application();

/// The font every figure draws its text in. Its size is in pixels, not points, so text
/// measured by a layout (QFontMetricsF of this font) is the size it is drawn at on a PNG and
/// in an SVG alike, whatever resolution the paint device reports.
QFont figure_font();

inline QColor qcolour(Rgb c) {
  return QColor(c.r, c.g, c.b);
}
inline QRectF qrect(const PixelRect& r) {
  return QRectF(r.x, r.y, r.width, r.height);
}

}  // namespace tocd::plot::detail

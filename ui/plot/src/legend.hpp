#pragma once

#include <QPainter>
#include <QRectF>
#include <QString>
#include <functional>
#include <utility>
#include <vector>

namespace tocd::plot::detail {

/// One legend line: its sample glyph is drawn by `glyph` centred on the given point.
struct LegendEntry {
  QString text;
  std::function<void(QPainter&, QPointF)> glyph;
};

/// A legend box in the top-left corner of `area`.
inline void draw_legend(QPainter& p, const QRectF& area, const std::vector<LegendEntry>& entries) {
  p.save();
  const double line = 20;
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const QPointF at(area.left() + 20, area.top() + 16 + static_cast<double>(k) * line);
    entries[k].glyph(p, at);
    p.setPen(Qt::black);
    p.drawText(QPointF(at.x() + 18, at.y() + 5), entries[k].text);
  }
  p.restore();
}

}  // namespace tocd::plot::detail

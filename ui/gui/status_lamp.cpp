#include "status_lamp.hpp"

#include <QPainter>

namespace tocd::gui {

StatusLamp::StatusLamp(QWidget* parent) : QWidget(parent) {
  setFixedSize(16, 16);
}

void StatusLamp::set_colour(const QColor& colour) {
  colour_ = colour;
  update();
}

void StatusLamp::paintEvent(QPaintEvent* /*event*/) {
  QPainter p(this);
  p.setRenderHint(QPainter::Antialiasing);
  p.setPen(colour_.darker(150));
  p.setBrush(colour_);
  p.drawEllipse(rect().adjusted(2, 2, -2, -2));
}

}  // namespace tocd::gui

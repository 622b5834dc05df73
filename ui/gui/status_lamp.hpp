#pragma once

#include <QColor>
#include <QWidget>

namespace tocd::gui {

/// A small round lamp (connection state, fault, interlock): a colour and a tooltip.
class StatusLamp : public QWidget {
  Q_OBJECT

 public:
  explicit StatusLamp(QWidget* parent = nullptr);
  void set_colour(const QColor& colour);
  QColor colour() const noexcept { return colour_; }
  QSize sizeHint() const override { return {16, 16}; }

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  QColor colour_{128, 128, 128};
};

namespace lamp {
inline QColor off() {
  return {128, 128, 128};
}
inline QColor ok() {
  return {40, 170, 60};
}
inline QColor busy() {
  return {230, 170, 20};
}
inline QColor bad() {
  return {210, 30, 30};
}
}  // namespace lamp

}  // namespace tocd::gui

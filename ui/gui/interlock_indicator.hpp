#pragma once

#include <QWidget>

class QLabel;

namespace tocd::gui {

class StatusLamp;

/// The interlock state at a glance: not armed (no run), armed and clear, or tripped with
/// the reason the engine gave (max load, vacuum loss, power over-range).
class InterlockIndicator : public QWidget {
  Q_OBJECT

 public:
  enum class State { idle, armed, tripped };

  explicit InterlockIndicator(QWidget* parent = nullptr);

  void set_idle();
  void set_armed(const QString& limits = {});
  void set_tripped(const QString& reason);

  State state() const noexcept { return state_; }
  QString text() const;

 private:
  State state_ = State::idle;
  StatusLamp* lamp_;
  QLabel* label_;
};

}  // namespace tocd::gui

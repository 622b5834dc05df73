#include "interlock_indicator.hpp"

#include <QHBoxLayout>
#include <QLabel>

#include "status_lamp.hpp"

namespace tocd::gui {

InterlockIndicator::InterlockIndicator(QWidget* parent)
    : QWidget(parent), lamp_(new StatusLamp(this)), label_(new QLabel(this)) {
  auto* row = new QHBoxLayout(this);
  row->setContentsMargins(0, 0, 0, 0);
  row->addWidget(lamp_);
  row->addWidget(label_, 1);
  set_idle();
}

void InterlockIndicator::set_idle() {
  state_ = State::idle;
  lamp_->set_colour(lamp::off());
  label_->setText(tr("Interlocks: not armed"));
}

void InterlockIndicator::set_armed(const QString& limits) {
  state_ = State::armed;
  lamp_->set_colour(lamp::ok());
  label_->setText(limits.isEmpty() ? tr("Interlocks: armed, clear")
                                   : tr("Interlocks: armed, clear (%1)").arg(limits));
}

void InterlockIndicator::set_tripped(const QString& reason) {
  state_ = State::tripped;
  lamp_->set_colour(lamp::bad());
  label_->setText(tr("INTERLOCK TRIPPED: %1").arg(reason));
}

QString InterlockIndicator::text() const {
  return label_->text();
}

}  // namespace tocd::gui

#include "instrument_panel.hpp"

#include <QFont>
#include <QGridLayout>
#include <QLabel>
#include <array>

#include "status_lamp.hpp"

namespace tocd::gui {

InstrumentPanel::InstrumentPanel(const QString& name, QWidget* parent)
    : QGroupBox(name, parent),
      connection_lamp_(new StatusLamp(this)),
      connection_label_(new QLabel(tr("not configured"), this)),
      identity_label_(new QLabel(QStringLiteral("—"), this)),
      value_label_(new QLabel(QStringLiteral("—"), this)),
      fault_lamp_(new StatusLamp(this)),
      fault_label_(new QLabel(tr("no fault"), this)) {
  auto* grid = new QGridLayout(this);
  grid->addWidget(connection_lamp_, 0, 0);
  grid->addWidget(connection_label_, 0, 1);
  grid->addWidget(identity_label_, 1, 0, 1, 2);
  QFont big = value_label_->font();
  big.setPointSizeF(big.pointSizeF() * 1.3);
  big.setBold(true);
  value_label_->setFont(big);
  value_label_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  grid->addWidget(value_label_, 2, 0, 1, 2);
  grid->addWidget(fault_lamp_, 3, 0);
  grid->addWidget(fault_label_, 3, 1);
  grid->setColumnStretch(1, 1);
  identity_label_->setWordWrap(true);
  fault_label_->setWordWrap(true);
  fault_lamp_->set_colour(lamp::off());
}

namespace {

/// How the panel shows one connection state: the lamp's colour and the label's text.
struct ConnectionLook {
  QColor (*colour)();
  const char* text;  ///< translated in InstrumentPanel's context
};

// In InstrumentPanel::Connection order: the table is indexed by the state. The assert catches a
// reordered or inserted state; a state added after `lost` needs its row here too.
using Connection = InstrumentPanel::Connection;
static_assert(static_cast<int>(Connection::absent) == 0 && static_cast<int>(Connection::connecting) == 1 &&
              static_cast<int>(Connection::connected) == 2 && static_cast<int>(Connection::lost) == 3);
const std::array<ConnectionLook, 4> kConnectionLooks{{
    {lamp::off, QT_TRANSLATE_NOOP("tocd::gui::InstrumentPanel", "not configured")},
    {lamp::busy, QT_TRANSLATE_NOOP("tocd::gui::InstrumentPanel", "connecting…")},
    {lamp::ok, QT_TRANSLATE_NOOP("tocd::gui::InstrumentPanel", "connected")},
    {lamp::bad, QT_TRANSLATE_NOOP("tocd::gui::InstrumentPanel", "connection lost")},
}};

}  // namespace

void InstrumentPanel::set_connection(Connection state, const QString& detail) {
  connection_ = state;
  const ConnectionLook& look = kConnectionLooks[static_cast<std::size_t>(state)];
  connection_lamp_->set_colour(look.colour());
  connection_label_->setText(tr(look.text));
  if (!detail.isEmpty())
    connection_label_->setText(connection_label_->text() + QStringLiteral(": ") + detail);
  connection_lamp_->setToolTip(connection_label_->text());
}

void InstrumentPanel::set_identity(const QString& vendor, const QString& model, const QString& serial,
                                   const QString& firmware) {
  identity_label_->setText(
      tr("%1 %2, s/n %3, fw %4")
          .arg(vendor, model, serial.isEmpty() ? tr("?") : serial, firmware.isEmpty() ? tr("?") : firmware));
}

void InstrumentPanel::set_value(const QString& quantity, double value, const QString& unit, int precision) {
  const QString line =
      QStringLiteral("%1: %2 %3").arg(quantity, QString::number(value, 'g', precision), unit);
  const qsizetype i = value_keys_.indexOf(quantity);
  if (i < 0) {
    value_keys_.push_back(quantity);
    value_lines_.push_back(line);
  } else {
    value_lines_[i] = line;
  }
  value_label_->setText(value_lines_.join(QLatin1Char('\n')));
}

void InstrumentPanel::set_fault(bool fault, const QString& text) {
  fault_ = fault;
  fault_lamp_->set_colour(fault ? lamp::bad() : lamp::off());
  fault_label_->setText(fault ? (text.isEmpty() ? tr("fault") : text) : tr("no fault"));
}

QString InstrumentPanel::identity_text() const {
  return identity_label_->text();
}
QString InstrumentPanel::value_text() const {
  return value_label_->text();
}
QString InstrumentPanel::fault_text() const {
  return fault_label_->text();
}

}  // namespace tocd::gui

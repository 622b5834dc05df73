#include "lab_view.hpp"

#include <QLabel>
#include <QVBoxLayout>
#include <map>

#include "instrument_panel.hpp"

namespace tocd::gui {

LabView::LabView(QWidget* parent) : QWidget(parent), lab_label_(new QLabel(tr("No lab connected"), this)) {
  auto* col = new QVBoxLayout(this);
  col->setContentsMargins(0, 0, 0, 0);
  QFont bold = lab_label_->font();
  bold.setBold(true);
  lab_label_->setFont(bold);
  col->addWidget(lab_label_);
  for (const InstrumentKind kind : kInstrumentKinds) {
    auto*& p = panels_[static_cast<std::size_t>(kind)];
    p = new InstrumentPanel(panel_title(kind), this);
    col->addWidget(p);
  }
}

QString LabView::lab_text() const {
  return lab_label_->text();
}

void LabView::show_connecting(const QString& what) {
  lab_label_->setText(tr("Connecting: %1").arg(what));
  for (auto* p : panels_) p->set_connection(InstrumentPanel::Connection::connecting);
}

void LabView::show_connected(const QString& lab_name, const QVector<InstrumentIdentity>& identities) {
  lab_label_->setText(tr("Lab: %1").arg(lab_name));
  for (auto* p : panels_) p->set_connection(InstrumentPanel::Connection::absent);
  for (const auto& id : identities) {
    InstrumentPanel* p = panel(id.kind);
    p->set_connection(InstrumentPanel::Connection::connected);
    p->set_identity(id.vendor, id.model, id.serial, id.firmware);
    p->set_fault(false);
  }
}

void LabView::show_disconnected() {
  lab_label_->setText(tr("No lab connected"));
  for (auto* p : panels_) p->set_connection(InstrumentPanel::Connection::absent);
}

void LabView::show_reading(const InstrumentReading& r) {
  InstrumentPanel* p = panel(r.kind);
  if (p->connection() != InstrumentPanel::Connection::connected) {
    p->set_connection(InstrumentPanel::Connection::connected);
  }
  // The idle poller's values are the drivers' raw readings (the tester's position is not yet
  // a displacement, the setpoint no channel); their units are those of the channels they feed.
  switch (r.kind) {
    case InstrumentKind::tester:
      p->set_value(tr("position"), r.value, unit_of(r.kind, "displacement"));
      p->set_value(tr("load"), r.value2, unit_of(r.kind, "load"));
      break;
    case InstrumentKind::power_meter:
      p->set_value(tr("power"), r.value, unit_of(r.kind, "power"));
      break;
    case InstrumentKind::vacuum:
      p->set_value(tr("pressure"), r.value, unit_of(r.kind, "pressure"));
      p->set_value(tr("setpoint"), r.value2, unit_of(r.kind, "pressure"));
      break;
  }
  p->set_fault(r.fault, r.fault_text);
}

void LabView::show_error(InstrumentKind kind, const QString& message) {
  panel(kind)->set_connection(InstrumentPanel::Connection::lost);
  panel(kind)->set_fault(true, message);
}

void LabView::show_live(const std::vector<LiveReading>& readings) {
  // Only the newest value of each channel matters for a panel; the panel and the unit are the
  // ones of the driver that describes the channel.
  std::map<std::string_view, double> last;
  for (const auto& r : readings) last[r.channel] = r.value;
  for (const InstrumentKind kind : kInstrumentKinds) {
    for (const auto& c : capabilities_of(kind).channels) {
      const auto it = last.find(c.name);
      if (it == last.end()) continue;
      panel(kind)->set_value(QString::fromUtf8(c.name.data(), static_cast<qsizetype>(c.name.size())),
                             it->second,
                             QString::fromUtf8(c.unit.data(), static_cast<qsizetype>(c.unit.size())));
    }
  }
}

void LabView::show_fault(const QString& message) {
  const QString m = message.toLower();
  InstrumentKind kind = InstrumentKind::tester;
  if (m.contains(QStringLiteral("power"))) kind = InstrumentKind::power_meter;
  if (m.contains(QStringLiteral("vacuum")) || m.contains(QStringLiteral("pressure"))) {
    kind = InstrumentKind::vacuum;
  }
  panel(kind)->set_fault(true, message);
}

}  // namespace tocd::gui

#pragma once

#include <QWidget>
#include <array>
#include <vector>

#include "backend_lab.hpp"
#include "backend_run.hpp"

class QLabel;

namespace tocd::gui {

class InstrumentPanel;

/// The instrument panels of the connected lab: tester, power meter, vacuum controller.
/// Fed by the lab's idle poller between runs and by the run's live readings during one.
class LabView : public QWidget {
  Q_OBJECT

 public:
  explicit LabView(QWidget* parent = nullptr);

  void show_connecting(const QString& what);
  void show_connected(const QString& lab_name, const QVector<InstrumentIdentity>& identities);
  void show_disconnected();
  void show_reading(const InstrumentReading& reading);
  void show_error(InstrumentKind kind, const QString& message);
  /// The latest of each channel in a batch of run readings.
  void show_live(const std::vector<LiveReading>& readings);
  /// A fault event of a run, routed to the panel it names (by the text).
  void show_fault(const QString& message);

  InstrumentPanel* panel(InstrumentKind kind) const { return panels_[static_cast<std::size_t>(kind)]; }
  QString lab_text() const;

 private:
  QLabel* lab_label_;
  std::array<InstrumentPanel*, 3> panels_{};
};

}  // namespace tocd::gui

#pragma once

#include <QDateTime>
#include <QTreeWidget>

namespace tocd::gui {

/// The event log: state changes, faults, interlock trips and operator actions, newest at
/// the bottom, coloured by severity, bounded so a long run cannot grow it without limit.
class EventLog : public QTreeWidget {
  Q_OBJECT

 public:
  enum class Severity { info, warning, error };

  explicit EventLog(QWidget* parent = nullptr, int max_entries = 5000);

  void add(Severity severity, const QString& source, const QString& text,
           const QDateTime& when = QDateTime::currentDateTimeUtc());

  int entry_count() const { return topLevelItemCount(); }
  QString text_of(int i) const;
  Severity severity_of(int i) const;
  /// Entries whose text contains `needle` (case-insensitive).
  int count_containing(const QString& needle) const;

 private:
  int max_entries_;
};

}  // namespace tocd::gui

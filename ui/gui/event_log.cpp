#include "event_log.hpp"

#include <QHeaderView>

namespace tocd::gui {

namespace {
constexpr int kSeverityRole = Qt::UserRole + 1;
}

EventLog::EventLog(QWidget* parent, int max_entries) : QTreeWidget(parent), max_entries_(max_entries) {
  setColumnCount(4);
  setHeaderLabels({tr("Time (UTC)"), tr("Severity"), tr("Source"), tr("Event")});
  setRootIsDecorated(false);
  setUniformRowHeights(true);
  setAlternatingRowColors(true);
  header()->setStretchLastSection(true);
  setColumnWidth(0, 160);
  setColumnWidth(1, 70);
  setColumnWidth(2, 110);
}

void EventLog::add(Severity severity, const QString& source, const QString& text, const QDateTime& when) {
  static const char* const kNames[] = {"info", "warning", "error"};
  auto* item = new QTreeWidgetItem({when.toUTC().toString(QStringLiteral("yyyy-MM-dd HH:mm:ss.zzz")),
                                    QString::fromLatin1(kNames[static_cast<int>(severity)]), source, text});
  item->setData(1, kSeverityRole, static_cast<int>(severity));
  if (severity == Severity::warning) {
    for (int c = 0; c < 4; ++c) item->setForeground(c, QColor(170, 110, 0));
  } else if (severity == Severity::error) {
    for (int c = 0; c < 4; ++c) item->setForeground(c, QColor(190, 20, 20));
  }
  addTopLevelItem(item);
  while (topLevelItemCount() > max_entries_) delete takeTopLevelItem(0);
  scrollToBottom();
}

QString EventLog::text_of(int i) const {
  const QTreeWidgetItem* item = topLevelItem(i);
  return item ? item->text(3) : QString();
}

EventLog::Severity EventLog::severity_of(int i) const {
  const QTreeWidgetItem* item = topLevelItem(i);
  return item ? static_cast<Severity>(item->data(1, kSeverityRole).toInt()) : Severity::info;
}

int EventLog::count_containing(const QString& needle) const {
  int n = 0;
  for (int i = 0; i < topLevelItemCount(); ++i) {
    if (topLevelItem(i)->text(3).contains(needle, Qt::CaseInsensitive)) ++n;
  }
  return n;
}

}  // namespace tocd::gui

#pragma once

#include <QWidget>

#include "backend_db.hpp"

class QLabel;
class QTableView;
class QTableWidget;

namespace tocd::gui {

class ComparisonChart;
class EventLog;
class LiveChart;
class StepTableModel;

/// The run browser: the runs of an opened database and, for the selected one, its step
/// table, measured-vs-simulated chart, stored time series and events (all read-only).
class BrowserView : public QWidget {
  Q_OBJECT

 public:
  explicit BrowserView(QWidget* parent = nullptr);

  void show_database(const QString& path, const QVector<RunListing>& runs);
  void show_runs(const QVector<RunListing>& runs);
  void show_run(const RunDetails& details);

  /// The run selected in the list, or 0.
  std::int64_t selected_run() const;
  void select_run(std::int64_t run_id);
  int run_count() const;
  StepTableModel* steps() const noexcept { return steps_; }
  ComparisonChart* comparison() const noexcept { return comparison_; }
  EventLog* events() const noexcept { return events_; }
  QString title_text() const;

 signals:
  void run_selected(qint64 run_id);

 private:
  QLabel* title_;
  QTableWidget* runs_;
  StepTableModel* steps_;
  QTableView* table_;
  ComparisonChart* comparison_;
  LiveChart* load_chart_;
  LiveChart* power_chart_;
  EventLog* events_;
  QVector<RunListing> listed_;
};

}  // namespace tocd::gui

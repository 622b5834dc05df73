#pragma once

#include <QWidget>
#include <optional>

#include "backend_db.hpp"

class QComboBox;
class QHBoxLayout;
class QLabel;
class QPushButton;
class QTableView;
class QTableWidget;

namespace tocd::gui {

class ComparisonChart;
class EventLog;
class HoldCourseChart;
class LiveChart;
class StepTableModel;

/// The run browser: the runs of an opened database and, for the selected one, its step
/// table, measured-vs-simulated chart, stored time series and events (all read-only). On
/// request, the selected run's steps predicted with the sample's own law, with its Monte Carlo
/// error and model band, join the chart; or the water time course: for the step chosen, the
/// T measured over its hold with the predicted T(t) points on top.
class BrowserView : public QWidget {
  Q_OBJECT

 public:
  explicit BrowserView(QWidget* parent = nullptr);

  void show_database(const QString& path, const QVector<RunListing>& runs);
  void show_runs(const QVector<RunListing>& runs);
  void show_run(const RunDetails& details);
  /// Draws the fitted law's predictions when they belong to the run on show.
  void show_fitted(const FittedLawView& view);
  void show_fit_progress(const QString& line);
  /// While a fit or a water time course runs, both buttons are off (one long job at a time).
  void set_fitting(bool fitting);
  /// Keeps the course when it belongs to the run on show and draws the chosen step's hold.
  void show_water_course(const WaterCourseView& view);
  void show_water_progress(const QString& line);
  /// Draws step `index` (0-based) of the water course on show; false when it has none.
  bool show_hold(int index);

  /// The run selected in the list, or 0.
  std::int64_t selected_run() const;
  void select_run(std::int64_t run_id);
  int run_count() const;
  StepTableModel* steps() const noexcept { return steps_; }
  ComparisonChart* comparison() const noexcept { return comparison_; }
  EventLog* events() const noexcept { return events_; }
  QString title_text() const;
  QString fit_text() const;
  QPushButton* fit_button() const noexcept { return fit_button_; }
  QPushButton* identify_button() const noexcept { return identify_button_; }
  QPushButton* water_button() const noexcept { return water_button_; }
  HoldCourseChart* hold_chart() const noexcept { return hold_chart_; }
  QComboBox* hold_step() const noexcept { return hold_step_; }
  QString water_text() const;

 signals:
  void run_selected(qint64 run_id);
  void fit_requested(qint64 run_id);
  /// Re-predict with the sample identified from the run (tocdlab compare --material identified).
  void identify_requested(qint64 run_id);
  void water_requested(qint64 run_id);

 private:
  // The constructor's parts, in the order it calls them.
  void set_up_job_buttons();
  void set_up_tables();
  /// The run list over the charts over the step table beside the events.
  QWidget* make_panes();
  /// The long jobs' buttons, each with the line it reports on.
  QHBoxLayout* make_job_row();
  void connect_job_buttons();
  /// A run picked in the list, a step in the table or the hold picker.
  void connect_pickers();
  /// The jobs' buttons are on while a run is on show and no job runs.
  void enable_job_buttons();

  QLabel* title_;
  QTableWidget* runs_;
  StepTableModel* steps_;
  QTableView* table_;
  ComparisonChart* comparison_;
  LiveChart* load_chart_;
  LiveChart* power_chart_;
  EventLog* events_;
  QPushButton* fit_button_;
  QPushButton* identify_button_;
  QLabel* fit_label_;
  QPushButton* water_button_;
  QComboBox* hold_step_;
  QLabel* water_label_;
  HoldCourseChart* hold_chart_;
  QVector<RunListing> listed_;
  std::int64_t shown_run_ = 0;
  bool fitting_ = false;
  std::optional<FittedLawView> fitted_;   ///< kept so that reloading the run keeps its fit
  std::optional<WaterCourseView> water_;  ///< likewise for the water time course
};

}  // namespace tocd::gui

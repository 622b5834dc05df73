#pragma once

#include <QWidget>
#include <limits>
#include <map>

#include "backend_run.hpp"

class QLabel;
class QProgressBar;
class QTableView;

namespace tocd::gui {

class ComparisonChart;
class EventLog;
class InterlockIndicator;
class LiveChart;
class StepTableModel;

/// The experiment as it happens: protocol and state line, progress by step, interlock
/// lamp, live charts (load vs displacement, power vs time, pressure vs time), the step table
/// and the measured-vs-simulated chart, and the event log. Shows; does not decide.
class RunView : public QWidget {
  Q_OBJECT

 public:
  explicit RunView(QWidget* parent = nullptr);

  void show_protocol(const QString& name, int step_count, const QString& interlocks);
  void begin_run(qint64 run_id, int step_count);
  void add_readings(const std::vector<LiveReading>& readings);
  void add_step(const RecordedStepView& step);
  /// `latency_s` < 0: not measured (PredictedStep::latency_s).
  void add_prediction(int step_index, double T, double T_stderr, double latency_s);
  void add_event(const QString& kind, const QString& message, int step_index);
  void show_state(acquisition::EngineState state, const QString& why);
  void show_progress(const acquisition::Progress& progress);
  void show_finished(acquisition::EngineState state, const QString& error);

  StepTableModel* steps() const noexcept { return steps_; }
  ComparisonChart* comparison() const noexcept { return comparison_; }
  EventLog* events() const noexcept { return events_; }
  InterlockIndicator* interlock() const noexcept { return interlock_; }
  QProgressBar* progress_bar() const noexcept { return progress_; }
  LiveChart* load_chart() const noexcept { return load_chart_; }
  LiveChart* power_chart() const noexcept { return power_chart_; }
  LiveChart* pressure_chart() const noexcept { return pressure_chart_; }
  QString state_text() const;

 private:
  QLabel* protocol_label_;
  QLabel* state_label_;
  QProgressBar* progress_;
  InterlockIndicator* interlock_;
  LiveChart* load_chart_;
  LiveChart* power_chart_;
  LiveChart* pressure_chart_;
  ComparisonChart* comparison_;
  StepTableModel* steps_;
  QTableView* table_;
  EventLog* events_;
  QString interlock_limits_;
  std::map<int, double> strain_of_step_;
  double last_displacement_ = std::numeric_limits<double>::quiet_NaN();
  int step_count_ = 0;
};

}  // namespace tocd::gui

#include "run_view.hpp"

#include <QGridLayout>
#include <QHeaderView>
#include <QLabel>
#include <QProgressBar>
#include <QSplitter>
#include <QTableView>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "comparison_chart.hpp"
#include "event_log.hpp"
#include "interlock_indicator.hpp"
#include "live_chart.hpp"
#include "step_table_model.hpp"
#include "widget_grid.hpp"

namespace tocd::gui {

using acquisition::EngineState;

namespace {

// The step table's row of a step just recorded.
StepRow measured_row(const RecordedStepView& s) {
  return {.step = s.index,
          .displacement_mm = s.displacement_mm,
          .nominal_strain = s.nominal_strain,
          .load_N = s.load_N,
          .measured_T = s.measured_T,
          .predicted_T = std::nullopt,  // the prediction comes on its own, later
          .predicted_T_stderr = std::nullopt,
          .prediction_latency_s = std::nullopt};
}

}  // namespace

RunView::RunView(QWidget* parent)
    : QWidget(parent),
      protocol_label_(new QLabel(tr("No protocol loaded"), this)),
      state_label_(new QLabel(tr("idle"), this)),
      progress_(new QProgressBar(this)),
      interlock_(new InterlockIndicator(this)),
      load_chart_(new LiveChart(
          {tr("Load vs displacement"), tr("displacement (mm)"), tr("load (N)"), 0.1, 0.0, 10000}, this)),
      power_chart_(
          new LiveChart({tr("Optical power"), tr("time (s)"), tr("power (W)"), 0.1, 120.0, 2000}, this)),
      pressure_chart_(new LiveChart(
          {tr("Vacuum pressure"), tr("time (s)"), tr("pressure (kPa)"), 0.1, 120.0, 2000}, this)),
      comparison_(new ComparisonChart(this)),
      steps_(new StepTableModel(this)),
      table_(new QTableView(this)),
      events_(new EventLog(this)) {
  progress_->setFormat(tr("step %v of %m"));
  progress_->setRange(0, 1);
  progress_->setValue(0);
  table_->setModel(steps_);
  table_->verticalHeader()->hide();
  table_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  table_->horizontalHeader()->setStretchLastSection(true);
  table_->setSelectionBehavior(QAbstractItemView::SelectRows);

  auto* status = new QGridLayout();
  status->addWidget(protocol_label_, 0, 0);
  status->addWidget(state_label_, 0, 1);
  status->addWidget(progress_, 1, 0);
  status->addWidget(interlock_, 1, 1);
  status->setColumnStretch(0, 2);
  status->setColumnStretch(1, 1);

  QWidget* charts = widget_grid(this, {{load_chart_, comparison_}, {power_chart_, pressure_chart_}});

  auto* bottom = new QSplitter(Qt::Horizontal, this);
  bottom->addWidget(table_);
  bottom->addWidget(events_);
  bottom->setStretchFactor(0, 3);
  bottom->setStretchFactor(1, 2);

  auto* split = new QSplitter(Qt::Vertical, this);
  split->addWidget(charts);
  split->addWidget(bottom);
  split->setStretchFactor(0, 3);
  split->setStretchFactor(1, 2);

  auto* col = new QVBoxLayout(this);
  col->addLayout(status);
  col->addWidget(split, 1);
}

QString RunView::state_text() const {
  return state_label_->text();
}

void RunView::show_protocol(const QString& name, int step_count, const QString& interlocks) {
  protocol_label_->setText(tr("Protocol: %1 (%2 steps)").arg(name).arg(step_count));
  interlock_limits_ = interlocks;
  step_count_ = step_count;
  progress_->setRange(0, std::max(1, step_count));
  progress_->setValue(0);
}

void RunView::begin_run(qint64 run_id, int step_count) {
  steps_->clear();
  comparison_->clear();
  load_chart_->clear();
  power_chart_->clear();
  pressure_chart_->clear();
  strain_of_step_.clear();
  last_displacement_ = std::numeric_limits<double>::quiet_NaN();
  step_count_ = step_count;
  progress_->setRange(0, std::max(1, step_count));
  progress_->setValue(0);
  interlock_->set_armed(interlock_limits_);
  events_->add(EventLog::Severity::info, tr("window"), tr("run %1 started").arg(run_id));
}

void RunView::add_readings(const std::vector<LiveReading>& readings) {
  for (const LiveReading& r : readings) {
    if (r.channel == "displacement") {
      last_displacement_ = r.value;
    } else if (r.channel == "load") {
      // The tester reads position and load together: pair the load with the latest
      // displacement.
      if (std::isfinite(last_displacement_)) load_chart_->add(r.t_s, last_displacement_, r.value);
    } else if (r.channel == "power") {
      power_chart_->add(r.t_s, r.t_s, r.value);
    } else if (r.channel == "pressure") {
      pressure_chart_->add(r.t_s, r.t_s, r.value);
    }
  }
}

void RunView::add_step(const RecordedStepView& s) {
  steps_->upsert_measured(measured_row(s));
  strain_of_step_[s.index] = s.nominal_strain;
  comparison_->set_measured(s.index, s.nominal_strain, s.measured_T);
  if (const StepRow* r = steps_->find(s.index); r && r->predicted_T) {
    comparison_->set_predicted(s.index, s.nominal_strain, *r->predicted_T, *r->predicted_T_stderr);
  }
  progress_->setValue(std::min(progress_->maximum(), s.index + 1));
}

void RunView::add_prediction(int step_index, double T, double T_stderr, double latency_s) {
  steps_->set_prediction(step_index, T, T_stderr, latency_s >= 0 ? std::optional(latency_s) : std::nullopt);
  const auto it = strain_of_step_.find(step_index);
  if (it != strain_of_step_.end()) comparison_->set_predicted(step_index, it->second, T, T_stderr);
}

void RunView::add_event(const QString& kind, const QString& message, int step_index) {
  auto severity = EventLog::Severity::info;
  if (kind == QLatin1String("fault") || kind == QLatin1String("retry") ||
      (kind == QLatin1String("prediction") && message.contains(QLatin1String("fail")))) {
    severity = EventLog::Severity::warning;
  }
  if (kind == QLatin1String("interlock")) {
    severity = EventLog::Severity::error;
    interlock_->set_tripped(message);
  }
  const QString text = step_index >= 0 ? tr("[step %1] %2").arg(step_index + 1).arg(message) : message;
  events_->add(severity, kind, text);
}

void RunView::show_state(EngineState state, const QString& why) {
  const QString name = QString::fromLatin1(acquisition::to_string(state).data());
  state_label_->setText(why.isEmpty() ? tr("State: %1").arg(name) : tr("State: %1 (%2)").arg(name, why));
  if (acquisition::is_terminal(state) && interlock_->state() != InterlockIndicator::State::tripped) {
    interlock_->set_idle();
  }
}

void RunView::show_progress(const acquisition::Progress& p) {
  if (p.step_count > 0 && p.step_count != progress_->maximum()) progress_->setMaximum(p.step_count);
  progress_->setValue(std::clamp(p.step_index, 0, progress_->maximum()));
  progress_->setFormat(
      tr("step %1 of %2, ETA %3 s").arg(p.step_index + 1).arg(p.step_count).arg(p.eta_s, 0, 'f', 0));
}

void RunView::show_finished(EngineState state, const QString& error) {
  if (state == EngineState::completed) progress_->setValue(progress_->maximum());
  progress_->setFormat(tr("%1: %2 of %3 steps, %4 predicted")
                           .arg(QString::fromLatin1(acquisition::to_string(state).data()))
                           .arg(steps_->rowCount())
                           .arg(step_count_)
                           .arg(steps_->predicted_count()));
  if (!error.isEmpty()) events_->add(EventLog::Severity::error, tr("engine"), error);
}

}  // namespace tocd::gui

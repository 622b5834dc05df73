#include "browser_view.hpp"

#include <QComboBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QSplitter>
#include <QTableView>
#include <QTableWidget>
#include <QVBoxLayout>

#include "comparison_chart.hpp"
#include "event_log.hpp"
#include "hold_course_chart.hpp"
#include "live_chart.hpp"
#include "step_table_model.hpp"
#include "tocd/db/location.hpp"
#include "widget_grid.hpp"

namespace tocd::gui {

BrowserView::BrowserView(QWidget* parent)
    : QWidget(parent),
      title_(new QLabel(tr("No database open (Data > Open database…)"), this)),
      runs_(new QTableWidget(this)),
      steps_(new StepTableModel(this)),
      table_(new QTableView(this)),
      comparison_(new ComparisonChart(this)),
      load_chart_(new LiveChart(
          {tr("Load vs displacement (stored)"), tr("displacement (mm)"), tr("load (N)"), 1e-9, 0.0, 100000},
          this)),
      power_chart_(new LiveChart(
          {tr("Optical power (stored)"), tr("time (s)"), tr("power (W)"), 1e-9, 0.0, 100000}, this)),
      events_(new EventLog(this)),
      fit_button_(new QPushButton(tr("Fit the sample's law (FE)"), this)),
      identify_button_(new QPushButton(tr("Identify the sample"), this)),
      fit_label_(new QLabel(this)),
      water_button_(new QPushButton(tr("Water time course (biphasic FE)"), this)),
      hold_step_(new QComboBox(this)),
      water_label_(new QLabel(this)),
      hold_chart_(new HoldCourseChart(this)) {
  set_up_job_buttons();
  set_up_tables();
  QWidget* panes = make_panes();
  QHBoxLayout* jobs = make_job_row();
  auto* col = new QVBoxLayout(this);
  col->addWidget(title_);
  col->addLayout(jobs);
  col->addWidget(panes, 1);
  connect_job_buttons();
  connect_pickers();
}

void BrowserView::set_up_job_buttons() {
  water_button_->setToolTip(
      tr("Drive the biphasic FE along the run's recorded pin displacement once and predict T(t) at points "
         "in every hold with water-content optics, next to the measured power (tocdlab compare --optics "
         "water); about a minute"));
  water_button_->setEnabled(false);
  hold_step_->setToolTip(tr("The step whose hold the time-course chart shows"));
  hold_step_->setEnabled(false);
  fit_button_->setToolTip(
      tr("Identify the run's own law from its held step loads through the FE and re-predict "
         "every step with it: fitted T with its Monte Carlo error and the model band over the fit's "
         "confidence laws (tocdlab compare --material fitted)"));
  fit_button_->setEnabled(false);
  identify_button_->setToolTip(
      tr("Identify the sample from the whole run (stiffness and relaxation, clearing and its delay, the "
         "clearing optics by Monte Carlo; minutes) and re-predict every held step with it: identified T "
         "with its Monte Carlo error and the band of the optical parameters' 95 % intervals (tocdlab compare "
         "--material identified)"));
  identify_button_->setEnabled(false);
}

void BrowserView::set_up_tables() {
  runs_->setColumnCount(7);
  runs_->setHorizontalHeaderLabels({tr("Run"), tr("Name"), tr("Status"), tr("Started (UTC)"), tr("Steps"),
                                    tr("Predictions"), tr("Operator")});
  runs_->setSelectionBehavior(QAbstractItemView::SelectRows);
  runs_->setSelectionMode(QAbstractItemView::SingleSelection);
  runs_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  runs_->verticalHeader()->hide();
  runs_->horizontalHeader()->setStretchLastSection(true);
  table_->setModel(steps_);
  table_->verticalHeader()->hide();
  table_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
}

QWidget* BrowserView::make_panes() {
  QWidget* charts = widget_grid(this, {{comparison_, load_chart_, power_chart_, hold_chart_}});
  auto* split = new QSplitter(Qt::Vertical, this);
  split->addWidget(runs_);
  split->addWidget(charts);
  auto* bottom = new QSplitter(Qt::Horizontal, this);
  bottom->addWidget(table_);
  bottom->addWidget(events_);
  split->addWidget(bottom);
  return split;
}

QHBoxLayout* BrowserView::make_job_row() {
  auto* row = new QHBoxLayout();
  row->addWidget(fit_button_);
  row->addWidget(identify_button_);
  row->addWidget(fit_label_, 1);
  row->addWidget(water_button_);
  row->addWidget(hold_step_);
  row->addWidget(water_label_, 1);
  return row;
}

void BrowserView::connect_job_buttons() {
  // Each asks for its job on the selected run; with none selected a click does nothing.
  const auto request = [this](QPushButton* button, void (BrowserView::*requested)(qint64)) {
    connect(button, &QPushButton::clicked, this, [this, requested] {
      if (const auto id = selected_run(); id != 0) emit(this->*requested)(id);
    });
  };
  request(fit_button_, &BrowserView::fit_requested);
  request(identify_button_, &BrowserView::identify_requested);
  request(water_button_, &BrowserView::water_requested);
}

void BrowserView::connect_pickers() {
  connect(hold_step_, &QComboBox::currentIndexChanged, this, [this](int i) {
    if (i >= 0) show_hold(hold_step_->itemData(i).toInt());
  });
  // Picking a step in the table shows its hold too, when the course has it.
  connect(table_->selectionModel(), &QItemSelectionModel::currentRowChanged, this,
          [this](const QModelIndex& current) {
            if (!water_ || !current.isValid()) return;
            const int i = hold_step_->findData(steps_->index(current.row(), 0).data(Qt::UserRole).toInt());
            if (i >= 0) hold_step_->setCurrentIndex(i);
          });

  connect(runs_, &QTableWidget::itemSelectionChanged, this, [this] {
    if (const auto id = selected_run(); id != 0) emit run_selected(id);
  });
}

void BrowserView::enable_job_buttons() {
  const bool can_start = shown_run_ != 0 && !fitting_;
  fit_button_->setEnabled(can_start);
  identify_button_->setEnabled(can_start);
  water_button_->setEnabled(can_start);
}

QString BrowserView::title_text() const {
  return title_->text();
}

void BrowserView::show_database(const QString& path, const QVector<RunListing>& runs) {
  title_->setText(
      tr("Database: %1 (read-only)").arg(QString::fromStdString(db::display_location(path.toStdString()))));
  steps_->clear();
  comparison_->clear();
  load_chart_->clear();
  power_chart_->clear();
  events_->clear();
  show_runs(runs);
}

void BrowserView::show_runs(const QVector<RunListing>& runs) {
  const std::int64_t keep = selected_run();
  listed_ = runs;
  const QSignalBlocker block(runs_);
  runs_->setRowCount(static_cast<int>(runs.size()));
  for (int i = 0; i < runs.size(); ++i) {
    const RunListing& r = runs[i];
    const QStringList cells = {QString::number(r.id),
                               r.name,
                               r.live ? tr("%1 (live)").arg(r.status) : r.status,
                               r.started_utc.toString(QStringLiteral("yyyy-MM-dd HH:mm:ss")),
                               QString::number(r.steps),
                               QString::number(r.predictions),
                               r.operator_name};
    for (int c = 0; c < cells.size(); ++c) runs_->setItem(i, c, new QTableWidgetItem(cells[c]));
    if (r.id == keep) runs_->selectRow(i);
  }
  runs_->resizeColumnsToContents();
}

void BrowserView::show_run(const RunDetails& d) {
  steps_->set_rows(d.rows);
  comparison_->clear();
  for (const StepRow& r : d.rows) {
    comparison_->set_measured(r.step, r.nominal_strain, r.measured_T);
    if (r.predicted_T)
      comparison_->set_predicted(r.step, r.nominal_strain, *r.predicted_T, *r.predicted_T_stderr);
  }
  shown_run_ = d.listing.id;
  if (fitted_ && fitted_->run_id == shown_run_) {
    show_fitted(*fitted_);
  } else {
    fitted_.reset();
    fit_label_->clear();
  }
  enable_job_buttons();
  if (water_ && water_->run_id == shown_run_) {
    show_water_course(*water_);
  } else {
    water_.reset();
    water_label_->clear();
    const QSignalBlocker block(hold_step_);
    hold_step_->clear();
    hold_step_->setEnabled(false);
    hold_chart_->clear();
  }
  load_chart_->clear();
  double k = 0;
  for (const QPointF& p : d.load_vs_displacement) load_chart_->add(k++, p.x(), p.y());
  load_chart_->refresh();
  power_chart_->clear();
  for (const SeriesView& s : d.series) {
    if (s.name != QLatin1String("power")) continue;
    for (const QPointF& p : s.points) power_chart_->add(p.x(), p.x(), p.y());
  }
  power_chart_->refresh();
  events_->clear();
  for (const EventView& e : d.events) {
    const auto sev = e.kind == QLatin1String("interlock") ? EventLog::Severity::error
                     : e.kind == QLatin1String("fault")   ? EventLog::Severity::warning
                                                          : EventLog::Severity::info;
    events_->add(sev, e.kind, e.message, e.utc);
  }
}

void BrowserView::show_fitted(const FittedLawView& v) {
  if (v.run_id != shown_run_) return;  // the user moved on to another run meanwhile
  fitted_ = v;
  comparison_->clear_fitted();
  for (const FittedPoint& p : v.points)
    comparison_->set_fitted(p.step, p.nominal_strain, p.T, p.T_stderr, p.band_lo, p.band_hi);
  fit_label_->setText(tr("Run %1, sample's law: %2").arg(v.run_id).arg(v.summary));
}

void BrowserView::show_fit_progress(const QString& line) {
  fit_label_->setText(line);
}

void BrowserView::set_fitting(bool fitting) {
  fitting_ = fitting;
  enable_job_buttons();
}

void BrowserView::show_water_course(const WaterCourseView& v) {
  if (v.run_id != shown_run_) return;  // the user moved on to another run meanwhile
  const int keep = hold_step_->currentIndex() >= 0 ? hold_step_->currentData().toInt() : -1;
  water_ = v;
  {
    const QSignalBlocker block(hold_step_);
    hold_step_->clear();
    for (const WaterStepView& s : v.steps)
      hold_step_->addItem(tr("step %1, %2 mm").arg(s.step + 1).arg(s.displacement_mm, 0, 'f', 3), s.step);
    hold_step_->setEnabled(!v.steps.empty());
  }
  water_label_->setText(tr("Run %1: %2").arg(v.run_id).arg(v.summary));
  // The deepest step that was computed shows the most clearing; else the first.
  int pick = v.steps.empty() ? -1 : v.steps.front().step;
  for (const WaterStepView& s : v.steps)
    for (const WaterPointView& p : s.points)
      if (p.computed) pick = s.step;
  if (keep >= 0 && hold_step_->findData(keep) >= 0) pick = keep;
  if (pick >= 0) {
    const QSignalBlocker block(hold_step_);
    hold_step_->setCurrentIndex(hold_step_->findData(pick));
    show_hold(pick);
  }
}

void BrowserView::show_water_progress(const QString& line) {
  water_label_->setText(line);
}

bool BrowserView::show_hold(int index) {
  if (!water_) return false;
  for (const WaterStepView& s : water_->steps)
    if (s.step == index) {
      hold_chart_->show_step(s);
      return true;
    }
  return false;
}

QString BrowserView::water_text() const {
  return water_label_->text();
}

QString BrowserView::fit_text() const {
  return fit_label_->text();
}

std::int64_t BrowserView::selected_run() const {
  const auto rows = runs_->selectionModel()->selectedRows();
  if (rows.isEmpty()) return 0;
  const int i = rows.front().row();
  return i >= 0 && i < listed_.size() ? listed_[i].id : 0;
}

void BrowserView::select_run(std::int64_t run_id) {
  for (int i = 0; i < listed_.size(); ++i) {
    if (listed_[i].id == run_id) runs_->selectRow(i);
  }
}

int BrowserView::run_count() const {
  return static_cast<int>(listed_.size());
}

}  // namespace tocd::gui

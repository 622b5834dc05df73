#include "main_window.hpp"

#include <QCloseEvent>
#include <QDir>
#include <QMessageBox>
#include <QSplitter>
#include <QStandardPaths>
#include <QStatusBar>
#include <QTabWidget>

#include "backend_db.hpp"
#include "backend_lab.hpp"
#include "backend_run.hpp"
#include "backend_study.hpp"
#include "browser_view.hpp"
#include "lab_view.hpp"
#include "run_view.hpp"
#include "simulation_view.hpp"
#include "tocd/core/version.hpp"
#include "tocd/mocks/default_sample.hpp"

namespace tocd::gui {

MainWindow::MainWindow(QWidget* parent) : MainWindow(std::make_unique<GuiSettings>(), parent) {}

MainWindow::MainWindow(std::unique_ptr<GuiSettings> settings, QWidget* parent)
    : QMainWindow(parent), settings_(std::move(settings)) {
  setWindowTitle(QStringLiteral("tocdlab %1").arg(QString::fromUtf8(tocd::version().data())));
  resize(1400, 900);
  sim_options_.clock_factor = settings_->clock_factor();
  // The simulated sample keeps clearing while a step holds, as `tocdlab demo`'s does: the power
  // chart shows T rising through each hold.
  sim_options_.delayed_clearing = mocks::kDefaultDelayedClearing;
  lab_ = new LabBackend(this);
  run_ = new RunBackend(this);
  browser_ = new RunBrowserBackend(this);
  study_ = new StudyBackend(this);
  build_views();
  build_actions();
  connect_backends();
  sim_view_->set_photons(settings_->photons());
  predictor_factory_ = [this] { return make_simulator_step_predictor(sim_view_->photons()); };
  record_db_path_ = settings_->last_database_path();
  if (record_db_path_.isEmpty()) {
    record_db_path_ = QDir(QStandardPaths::writableLocation(QStandardPaths::AppDataLocation))
                          .filePath(QStringLiteral("runs.tocdlab"));
  }
  settings_->restore_window(*this);
  statusBar()->showMessage(tr("No lab connected. Lab > Simulated lab starts the simulated instruments."));
  update_actions();
}

MainWindow::~MainWindow() {
  // The backends stop their threads in their destructors; the run goes first (it owns the
  // instruments), then the lab's poller.
  delete run_;
  run_ = nullptr;
  delete lab_;
  lab_ = nullptr;
}

void MainWindow::build_views() {
  lab_view_ = new LabView(this);
  run_view_ = new RunView(this);
  browser_view_ = new BrowserView(this);
  sim_view_ = new SimulationView(this);

  auto* experiment = new QSplitter(Qt::Horizontal, this);
  experiment->addWidget(lab_view_);
  experiment->addWidget(run_view_);
  experiment->setStretchFactor(0, 0);
  experiment->setStretchFactor(1, 1);
  lab_view_->setMaximumWidth(320);

  tabs_ = new QTabWidget(this);
  tabs_->addTab(experiment, tr("Experiment"));
  tabs_->addTab(browser_view_, tr("Run browser"));
  tabs_->addTab(sim_view_, tr("Simulation"));
  setCentralWidget(tabs_);
}

void MainWindow::connect_backends() {
  wire_lab_signals();
  wire_run_signals();
  wire_browser_signals();
  wire_simulation_signals();
}

void MainWindow::wire_lab_signals() {
  connect(lab_, &LabBackend::connected, this,
          [this](const QString& name, const QVector<InstrumentIdentity>& ids) {
            lab_busy_ = false;
            lab_view_->show_connected(name, ids);
            statusBar()->showMessage(tr("Connected to %1").arg(name));
            update_actions();
            emit lab_ready();
          });
  connect(lab_, &LabBackend::disconnected, this, [this] {
    lab_view_->show_disconnected();
    update_actions();
  });
  connect(lab_, &LabBackend::reading, lab_view_, &LabView::show_reading);
  connect(lab_, &LabBackend::instrument_error, lab_view_, &LabView::show_error);
  connect(lab_, &LabBackend::failed, this, [this](const QString& action, const QString& message) {
    lab_busy_ = false;
    lab_view_->show_disconnected();
    show_error(action, message);
    update_actions();
  });
}

void MainWindow::wire_run_signals() {
  connect(run_, &RunBackend::started, this, [this](qint64 run_id, int step_count) {
    run_view_->begin_run(run_id, step_count);
    statusBar()->showMessage(tr("Run %1 recording into %2").arg(run_id).arg(record_db_path_));
    update_actions();
    emit run_started(run_id);
  });
  connect(run_, &RunBackend::live_readings, this, [this](const std::vector<LiveReading>& r) {
    run_view_->add_readings(r);
    lab_view_->show_live(r);
  });
  connect(run_, &RunBackend::step_recorded, run_view_, &RunView::add_step);
  connect(run_, &RunBackend::prediction_arrived, run_view_, &RunView::add_prediction);
  connect(run_, &RunBackend::event_recorded, this,
          [this](const QString& kind, const QString& message, int step) {
            run_view_->add_event(kind, message, step);
            if (kind == QLatin1String("fault")) lab_view_->show_fault(message);
          });
  connect(run_, &RunBackend::state_changed, this, [this](acquisition::EngineState s, const QString& why) {
    run_view_->show_state(s, why);
    update_actions();
  });
  connect(run_, &RunBackend::progress, run_view_, &RunView::show_progress);
  connect(run_, &RunBackend::finished, this, [this](acquisition::EngineState s, const QString& error) {
    run_view_->show_finished(s, error);
    statusBar()->showMessage(tr("Run %1 ended: %2")
                                 .arg(run_->run_id())
                                 .arg(QString::fromLatin1(acquisition::to_string(s).data())));
    lab_->reconnect();  // the engine owned the instruments; the panels get them back
    if (browser_->path() == record_db_path_) browser_->refresh();
    update_actions();
    emit run_finished(s);
  });
  connect(run_, &RunBackend::failed, this, [this](const QString& action, const QString& message) {
    show_error(action, message);
    lab_->reconnect();
    update_actions();
  });
}

void MainWindow::wire_browser_signals() {
  connect(browser_, &RunBrowserBackend::database_opened, this,
          [this](const QString& path, const QVector<RunListing>& runs) {
            browser_view_->show_database(path, runs);
            settings_->add_recent_database(path);
          });
  connect(browser_, &RunBrowserBackend::runs_listed, browser_view_, &BrowserView::show_runs);
  connect(browser_, &RunBrowserBackend::run_loaded, browser_view_, &BrowserView::show_run);
  connect(browser_, &RunBrowserBackend::exported, this,
          [this](const QString& path) { statusBar()->showMessage(tr("Exported %1").arg(path)); });
  connect(browser_, &RunBrowserBackend::failed, this, [this](const QString& action, const QString& message) {
    browser_view_->set_fitting(browser_->fitting());  // a failed fit frees its button
    show_error(action, message);
  });
  connect(browser_view_, &BrowserView::run_selected, this, [this](qint64 id) {
    browser_->load_run(id);
    update_actions();
  });
  connect(browser_view_, &BrowserView::fit_requested, this, [this](qint64 id) {
    browser_view_->set_fitting(true);
    browser_->fit_law(id);
  });
  connect(browser_view_, &BrowserView::identify_requested, this, [this](qint64 id) {
    browser_view_->set_fitting(true);
    browser_->fit_law(id, QStringLiteral("identified"));
  });
  connect(browser_, &RunBrowserBackend::fit_progress, browser_view_, &BrowserView::show_fit_progress);
  connect(browser_view_, &BrowserView::water_requested, this, [this](qint64 id) {
    browser_view_->set_fitting(true);
    browser_->water_course(id);
  });
  connect(browser_, &RunBrowserBackend::water_progress, browser_view_, &BrowserView::show_water_progress);
  connect(browser_, &RunBrowserBackend::water_course_ready, this, [this](const WaterCourseView& v) {
    browser_view_->set_fitting(false);
    browser_view_->show_water_course(v);
    statusBar()->showMessage(tr("Run %1: water time course computed").arg(v.run_id));
  });
  connect(browser_, &RunBrowserBackend::law_fitted, this, [this](const FittedLawView& v) {
    browser_view_->set_fitting(false);
    browser_view_->show_fitted(v);
    statusBar()->showMessage(tr("Run %1: predicted with the sample's own law").arg(v.run_id));
  });
}

void MainWindow::wire_simulation_signals() {
  connect(sim_view_, &SimulationView::predict_requested, this, &MainWindow::predict_one);
  connect(sim_view_, &SimulationView::study_requested, this, &MainWindow::run_study);
  connect(study_, &StudyBackend::started, sim_view_, &SimulationView::begin);
  connect(study_, &StudyBackend::row_done, sim_view_, &SimulationView::add_row);
  connect(study_, &StudyBackend::finished, this, [this](double seconds) {
    sim_view_->finish(seconds);
    update_actions();
  });
  connect(study_, &StudyBackend::failed, this, [this](const QString& action, const QString& message) {
    sim_view_->fail(message);
    show_error(action, message);
    update_actions();
  });
}

void MainWindow::show_error(const QString& action, const QString& message) {
  last_error_ = tr("%1: %2").arg(action, message);
  ++error_count_;
  statusBar()->showMessage(last_error_);
  // Window-modal and non-blocking: the window keeps updating (a run may be going on).
  auto* box = new QMessageBox(QMessageBox::Warning, tr("tocdlab"), action, QMessageBox::Ok, this);
  box->setInformativeText(message);
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->setObjectName(QStringLiteral("error_dialog"));
  box->open();
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (run_ && run_->is_active()) {
    const auto answer = QMessageBox::question(
        this, tr("tocdlab"), tr("A run is recording. Abort it and close? Everything recorded is kept."));
    if (answer != QMessageBox::Yes) {
      event->ignore();
      return;
    }
    run_->abort();
  }
  settings_->set_photons(sim_view_->photons());
  settings_->save_window(*this);
  settings_->sync();
  event->accept();
}

}  // namespace tocd::gui

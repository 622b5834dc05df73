// The window's menus, toolbar and the command behind each action.
#include <QAction>
#include <QDir>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QInputDialog>
#include <QLineEdit>
#include <QMenuBar>
#include <QStandardPaths>
#include <QStatusBar>
#include <QTabWidget>
#include <QToolBar>

#include "backend_db.hpp"
#include "backend_lab.hpp"
#include "backend_run.hpp"
#include "backend_study.hpp"
#include "browser_view.hpp"
#include "lab_view.hpp"
#include "main_window.hpp"
#include "run_view.hpp"
#include "simulation_view.hpp"

namespace tocd::gui {

void MainWindow::build_actions() {
  const auto make = [this](const QString& text, const QString& name, void (MainWindow::*slot)(),
                           const QKeySequence& key = {}) {
    auto* a = new QAction(text, this);
    a->setObjectName(name);
    if (!key.isEmpty()) a->setShortcut(key);
    if (slot) connect(a, &QAction::triggered, this, slot);
    return a;
  };
  actions_.open_lab = make(tr("Open lab config…"), QStringLiteral("open_lab"), &MainWindow::open_lab);
  actions_.simulated_lab =
      make(tr("Simulated lab"), QStringLiteral("simulated_lab"), &MainWindow::start_simulated_lab);
  actions_.disconnect_lab = make(tr("Disconnect"), QStringLiteral("disconnect_lab"), nullptr);
  connect(actions_.disconnect_lab, &QAction::triggered, this, [this] { lab_->disconnect_lab(); });
  actions_.open_protocol = make(tr("Open protocol…"), QStringLiteral("open_protocol"),
                                &MainWindow::open_protocol, QKeySequence::Open);
  actions_.choose_record_database = make(tr("Record into database…"), QStringLiteral("record_database"),
                                         &MainWindow::choose_record_database);
  actions_.start = make(tr("Start"), QStringLiteral("start"), &MainWindow::start_run);
  actions_.pause = make(tr("Pause"), QStringLiteral("pause"), nullptr);
  connect(actions_.pause, &QAction::triggered, this, [this] { run_->pause(); });
  actions_.resume = make(tr("Resume"), QStringLiteral("resume"), nullptr);
  connect(actions_.resume, &QAction::triggered, this, [this] { run_->resume(); });
  actions_.abort = make(tr("Abort"), QStringLiteral("abort"), nullptr);
  connect(actions_.abort, &QAction::triggered, this, [this] { run_->abort(); });
  actions_.open_database =
      make(tr("Open database…"), QStringLiteral("open_database"), &MainWindow::open_database);
  actions_.open_server = make(tr("Open server database…"), QStringLiteral("open_server_database"),
                              &MainWindow::open_server_database);
  actions_.export_csv = make(tr("Export run as CSV…"), QStringLiteral("export_csv"), &MainWindow::export_csv);
  actions_.predict = make(tr("Predict one step"), QStringLiteral("predict"), &MainWindow::predict_one);
  actions_.run_study = make(tr("Run the study"), QStringLiteral("run_study"), &MainWindow::run_study);
  actions_.quit = make(tr("Quit"), QStringLiteral("quit"), nullptr, QKeySequence::Quit);
  connect(actions_.quit, &QAction::triggered, this, &QWidget::close);

  QMenu* lab = menuBar()->addMenu(tr("&Lab"));
  lab->addAction(actions_.open_lab);
  lab->addAction(actions_.simulated_lab);
  lab->addAction(actions_.disconnect_lab);
  lab->addSeparator();
  lab->addAction(actions_.quit);
  QMenu* run = menuBar()->addMenu(tr("&Run"));
  for (QAction* a : {actions_.open_protocol, actions_.choose_record_database}) run->addAction(a);
  run->addSeparator();
  for (QAction* a : {actions_.start, actions_.pause, actions_.resume, actions_.abort}) run->addAction(a);
  QMenu* data = menuBar()->addMenu(tr("&Data"));
  data->addAction(actions_.open_database);
  data->addAction(actions_.open_server);
  data->addAction(actions_.export_csv);
  QMenu* sim = menuBar()->addMenu(tr("&Simulation"));
  sim->addAction(actions_.predict);
  sim->addAction(actions_.run_study);

  QToolBar* bar = addToolBar(tr("Run control"));
  bar->setObjectName(QStringLiteral("run_control"));
  for (QAction* a : {actions_.simulated_lab, actions_.open_protocol}) bar->addAction(a);
  bar->addSeparator();
  for (QAction* a : {actions_.start, actions_.pause, actions_.resume, actions_.abort}) bar->addAction(a);
  bar->addSeparator();
  bar->addAction(actions_.open_database);
}

void MainWindow::update_actions() {
  const bool connected = lab_->is_connected();
  const bool active = run_->is_active();
  const auto state = run_->state();
  const bool paused = state == acquisition::EngineState::paused;
  actions_.open_lab->setEnabled(!active && !lab_busy_);
  actions_.simulated_lab->setEnabled(!active && !lab_busy_);
  actions_.disconnect_lab->setEnabled(connected && !active);
  actions_.open_protocol->setEnabled(!active);
  actions_.choose_record_database->setEnabled(!active);
  actions_.start->setEnabled(connected && protocol_.has_value() && !active);
  actions_.pause->setEnabled(active && run_->engine() && !paused && !acquisition::is_terminal(state));
  actions_.resume->setEnabled(active && paused);
  actions_.abort->setEnabled(active && run_->engine() && !acquisition::is_terminal(state));
  actions_.export_csv->setEnabled(browser_->is_open() && browser_view_->selected_run() != 0);
  actions_.predict->setEnabled(StudyBackend::available() && !study_->busy());
  actions_.run_study->setEnabled(StudyBackend::available() && !study_->busy());
}

QString MainWindow::ask_file(FileRequest request) {
  if (choose_file_) return choose_file_(request);
  switch (request) {
    case FileRequest::lab_config:
      return QFileDialog::getOpenFileName(this, tr("Open lab config"), settings_->last_lab_path(),
                                          tr("Lab config (*.toml);;All files (*)"));
    case FileRequest::protocol:
      return QFileDialog::getOpenFileName(this, tr("Open protocol"), settings_->last_protocol_path(),
                                          tr("Protocol (*.toml);;All files (*)"));
    case FileRequest::record_database:
      return QFileDialog::getSaveFileName(this, tr("Record into database"), record_db_path_,
                                          tr("tocdlab database (*.tocdlab *.sqlite *.db);;All files (*)"),
                                          nullptr, QFileDialog::DontConfirmOverwrite);
    case FileRequest::open_database:
      return QFileDialog::getOpenFileName(this, tr("Open database"), settings_->last_database_path(),
                                          tr("tocdlab database (*.tocdlab *.sqlite *.db);;All files (*)"));
    case FileRequest::open_server:
      // No password here: libpq takes it from ~/.pgpass or PGPASSWORD.
      return QInputDialog::getText(this, tr("Open server database"),
                                   tr("PostgreSQL connection URI (postgresql://user@host/database):"),
                                   QLineEdit::Normal, QStringLiteral("postgresql://"));
    case FileRequest::export_csv:
      return QFileDialog::getSaveFileName(this, tr("Export run as CSV"), QString(), tr("CSV (*.csv)"));
  }
  return {};
}

void MainWindow::open_lab() {
  const QString path = ask_file(FileRequest::lab_config);
  if (path.isEmpty()) return;
  settings_->set_last_lab_path(path);
  lab_busy_ = true;
  lab_view_->show_connecting(QFileInfo(path).fileName());
  lab_->connect_lab_file(path);
  update_actions();
}

void MainWindow::set_sample_truth(const mocks::SampleTruth& truth) {
  mocks::validate(truth);
  sample_truth_ = truth;
  const mocks::SimulatedLabOptions o = mocks::simulated_lab_options(truth);
  sim_options_.relaxation_fraction = o.relaxation_fraction;
  sim_options_.relaxation_time_s = o.relaxation_time_s;
  sim_options_.delayed_clearing = o.delayed_clearing;
  sim_options_.delayed_clearing_time_s = o.delayed_clearing_time_s;
}

void MainWindow::start_simulated_lab() {
  lab_busy_ = true;
  lab_view_->show_connecting(tr("simulated lab"));
  lab_->connect_simulated(sim_options_, sample_truth_);
  update_actions();
}

bool MainWindow::load_protocol_text(const QString& text, const QString& source_name) {
  try {
    protocol_ = acquisition::parse_protocol(text.toStdString(), source_name.toStdString());
  } catch (const std::exception& e) {
    show_error(tr("Reading protocol %1").arg(source_name), QString::fromUtf8(e.what()));
    update_actions();
    return false;
  }
  const auto& p = *protocol_;
  const QString limits = tr("max load %1 N").arg(p.interlocks.max_load_N);
  run_view_->show_protocol(QString::fromStdString(p.name), static_cast<int>(p.steps.size()), limits);
  statusBar()->showMessage(tr("Protocol %1 loaded: %2 steps").arg(source_name).arg(p.steps.size()));
  update_actions();
  return true;
}

bool MainWindow::load_protocol_file(const QString& path) {
  QFile f(path);
  if (!f.open(QIODevice::ReadOnly)) {
    show_error(tr("Reading protocol %1").arg(path), f.errorString());
    return false;
  }
  settings_->set_last_protocol_path(path);
  return load_protocol_text(QString::fromUtf8(f.readAll()), QFileInfo(path).fileName());
}

void MainWindow::open_protocol() {
  const QString path = ask_file(FileRequest::protocol);
  if (!path.isEmpty()) load_protocol_file(path);
}

void MainWindow::set_record_database(const QString& path) {
  record_db_path_ = path;
}

void MainWindow::choose_record_database() {
  const QString path = ask_file(FileRequest::record_database);
  if (path.isEmpty()) return;
  set_record_database(path);
  settings_->set_last_database_path(path);
}

void MainWindow::start_run() {
  if (!protocol_ || !lab_->is_connected() || run_->is_active()) return;
  QDir().mkpath(QFileInfo(record_db_path_).absolutePath());
  acquisition::EngineOptions options;
  options.clock_factor = lab_->clock_factor();
  options.lab_config_text = lab_->config_text().toStdString();
  options.operator_name = qEnvironmentVariable("USER").toStdString();
  auto predictor = predictor_factory_ ? predictor_factory_() : nullptr;
  run_->start(*protocol_, record_db_path_, lab_->take_instruments(), options, std::move(predictor));
  tabs_->setCurrentIndex(0);
  update_actions();
}

void MainWindow::open_database() {
  const QString path = ask_file(FileRequest::open_database);
  if (path.isEmpty()) return;
  settings_->set_last_database_path(path);
  browser_->open_database(path);
  tabs_->setCurrentWidget(browser_view_);
}

void MainWindow::open_server_database() {
  const QString uri = ask_file(FileRequest::open_server).trimmed();
  if (uri.isEmpty() || uri == QStringLiteral("postgresql://")) return;
  browser_->open_database(uri);
  tabs_->setCurrentWidget(browser_view_);
}

void MainWindow::export_csv() {
  const std::int64_t id = browser_view_->selected_run();
  if (id == 0) return;
  const QString path = ask_file(FileRequest::export_csv);
  if (!path.isEmpty()) browser_->export_csv(id, path);
}

namespace {
QString fluence_dir() {
  return QDir(QStandardPaths::writableLocation(QStandardPaths::CacheLocation))
      .filePath(QStringLiteral("fluence"));
}
}  // namespace

void MainWindow::predict_one() {
  if (study_->busy()) return;
  tabs_->setCurrentWidget(sim_view_);
  settings_->set_photons(sim_view_->photons());
  study_->predict(sim_view_->displacement_mm(), sim_view_->thickness_mm(), sim_view_->optics(),
                  sim_view_->photons(), fluence_dir());
  update_actions();
}

void MainWindow::run_study() {
  if (study_->busy()) return;
  tabs_->setCurrentWidget(sim_view_);
  settings_->set_photons(sim_view_->photons());
  study_->run_study(sim_view_->photons(), fluence_dir());
  update_actions();
}

}  // namespace tocd::gui

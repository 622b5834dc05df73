#include "demo.hpp"

#include <QAction>
#include <QTimer>
#include <cmath>
#include <cstdio>

#include "backend_lab.hpp"
#include "backend_run.hpp"
#include "backend_study.hpp"
#include "live_chart.hpp"
#include "main_window.hpp"
#include "run_view.hpp"
#include "step_table_model.hpp"
#include "tocd/acquisition/lab_session.hpp"

namespace tocd::gui {

QString demo_protocol_toml() {
  const std::string_view text = acquisition::demo_protocol_text();
  return QString::fromUtf8(text.data(), static_cast<qsizetype>(text.size()));
}

DemoDriver::DemoDriver(MainWindow& window, QString screenshot_path, QObject* parent)
    : QObject(parent), window_(window), screenshot_(std::move(screenshot_path)) {
  connect(&window_, &MainWindow::lab_ready, this, &DemoDriver::on_lab_ready);
  connect(&window_, &MainWindow::run_finished, this, &DemoDriver::on_finished);
  // The engine logs states and steps; predictions and failures get a line here.
  RunBackend* run = window_.run_backend();
  connect(run, &RunBackend::prediction_arrived, this, [](int step, double T, double err) {
    std::fprintf(stderr, "demo: step %d predicted: T = %.4f +/- %.4f\n", step + 1, T, err);
  });
  // Nobody is there to resume a paused demo run: it ends it, and the demo fails.
  connect(run, &RunBackend::state_changed, this,
          [this, run](acquisition::EngineState state, const QString& why) {
            if (state != acquisition::EngineState::paused) return;
            std::fprintf(stderr, "demo: the run paused (%s); aborting it\n", qPrintable(why));
            paused_ = true;
            run->abort();
          });
  connect(run, &RunBackend::failed, this, [this](const QString& action, const QString& message) {
    std::fprintf(stderr, "demo: %s: %s\n", qPrintable(action), qPrintable(message));
    emit done(1);
  });
  connect(window_.lab_backend(), &LabBackend::failed, this,
          [this](const QString& action, const QString& message) {
            if (started_) return;
            std::fprintf(stderr, "demo: %s: %s\n", qPrintable(action), qPrintable(message));
            emit done(1);
          });
}

void DemoDriver::start() {
  window_.actions().simulated_lab->trigger();
}

void DemoDriver::on_lab_ready() {
  if (started_) return;  // the lab reconnects after the run; start only once
  started_ = true;
  if (!window_.load_protocol_text(demo_protocol_toml(), QStringLiteral("demo protocol"))) {
    emit done(2);
    return;
  }
  window_.actions().start->trigger();
}

void DemoDriver::on_finished(acquisition::EngineState state) {
  const StepTableModel* steps = window_.run_view()->steps();
  const bool want_predictions = StudyBackend::available();
  bool ok = !paused_ && state == acquisition::EngineState::completed && steps->rowCount() > 0;
  for (const StepRow& r : steps->rows()) {
    ok = ok && std::isfinite(r.measured_T) && (!want_predictions || r.predicted_T.has_value());
  }
  take_screenshot_and_quit(ok ? 0 : 1);
}

void DemoDriver::take_screenshot_and_quit(int exit_code) {
  // Draw what is buffered before the picture is taken.
  RunView* v = window_.run_view();
  for (LiveChart* c : {v->load_chart(), v->power_chart(), v->pressure_chart()}) c->refresh();
  QTimer::singleShot(300, this, [this, exit_code] {
    int code = exit_code;
    if (!screenshot_.isEmpty() && !window_.grab().save(screenshot_)) code = 3;
    emit done(code);
  });
}

}  // namespace tocd::gui

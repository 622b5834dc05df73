// The window driven through its own actions against the simulated lab and the real engine
// and database, with a fast stand-in predictor.
#include <QAction>
#include <QFile>
#include <QMessageBox>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <chrono>
#include <cmath>
#include <thread>

#include "backend_db.hpp"
#include "backend_lab.hpp"
#include "backend_run.hpp"
#include "browser_view.hpp"
#include "comparison_chart.hpp"
#include "event_log.hpp"
#include "instrument_panel.hpp"
#include "lab_view.hpp"
#include "live_chart.hpp"
#include "main_window.hpp"
#include "run_view.hpp"
#include "step_table_model.hpp"
#include "test_settings.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/mocks/tissue.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/protocol_text.hpp"

using namespace tocd;
using namespace tocd::gui;
using acquisition::EngineState;

namespace {

// Answers at once-ish from a thread of its own: T = 0.9 measured + 0.01, s.e. 0.002.
class FastPredictor : public acquisition::StepPredictor {
 public:
  std::future<acquisition::PredictedStep> predict(const acquisition::RecordedStep& step) override {
    return std::async(std::launch::async, [step] {
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
      acquisition::PredictedStep p;
      p.T = 0.9 * step.measured_T + 0.01;
      p.T_stderr = 0.002;
      p.config_json = R"({"predictor":"test"})";
      return p;
    });
  }
};

// A short protocol of the window tests' own (the demo protocol's 7 steps with 2 s holds and
// 5 s windows would make every test a minute long): the given steps, 0.5 s holds, 1 s windows,
// a 100 Hz tester.
QString short_protocol(const std::string& steps = "0.25, 0.5, 0.75, 1.0, 1.25, 1.5") {
  tocd::test::PinProtocolText p;
  p.name = "window test pin compression";
  p.tissue = "simulated skin";
  p.approach_speed_mm_per_s = 0.5;
  p.retract_speed_mm_per_s = 2.0;
  p.displacements_mm = steps;
  p.settle->max_wait_s = 8;
  p.tester_Hz = 100;
  p.power_Hz = 10;
  p.pressure_Hz = 10;
  p.max_load_N = 40;
  return QString::fromStdString(tocd::test::protocol_toml(p));
}

}  // namespace

class WindowRunTest : public QObject {
  Q_OBJECT

 private slots:
  void init();
  void cleanup();
  void demo_run_fills_the_step_table_from_the_engine();
  void pause_resume_abort_reach_the_engine();
  void bad_files_show_an_error_dialog();

 private:
  std::unique_ptr<MainWindow> make_window();
  void connect_simulated_lab(MainWindow& w);
  QString write(const QString& name, const QString& text);

  std::unique_ptr<QTemporaryDir> dir_;
  QString next_file_;
};

void WindowRunTest::init() {
  dir_ = std::make_unique<QTemporaryDir>();
  QVERIFY(dir_->isValid());
}

void WindowRunTest::cleanup() {
  dir_.reset();
}

QString WindowRunTest::write(const QString& name, const QString& text) {
  const QString path = dir_->filePath(name);
  return tocd::test::write_file(path.toStdString(), text.toStdString()) ? path : QString();
}

std::unique_ptr<MainWindow> WindowRunTest::make_window() {
  auto w = std::make_unique<MainWindow>(testing::settings_in(*dir_));
  w->set_file_chooser([this](MainWindow::FileRequest) { return next_file_; });
  w->set_predictor_factory([] { return std::make_shared<FastPredictor>(); });
  auto lab = w->simulated_lab_options();
  // 4x, not faster: the instrument-lost interlock counts protocol seconds, and at 10x a
  // loaded 2-core machine stalling the vacuum twin's pty for ~1.5 s of wall time already
  // reads as a lost controller (seen once under a parallel build).
  lab.clock_factor = 4.0;
  // The window's mechanics, not the sample: the analytic stand-in is ready at once.
  lab.tissue = tocd::mocks::make_analytic_tissue(2.5);
  w->set_simulated_lab_options(lab);
  w->set_record_database(dir_->filePath(QStringLiteral("runs.tocdlab")));
  w->show();
  return w;
}

void WindowRunTest::connect_simulated_lab(MainWindow& w) {
  QSignalSpy ready(&w, &MainWindow::lab_ready);
  QVERIFY(w.actions().simulated_lab->isEnabled());
  w.actions().simulated_lab->trigger();
  QVERIFY(ready.wait(20000));
  QVERIFY(w.lab_backend()->is_connected());
  InstrumentPanel* tester = w.lab_view()->panel(InstrumentKind::tester);
  QVERIFY(tester->connection() == InstrumentPanel::Connection::connected);
  QVERIFY(!tester->identity_text().isEmpty());
  // The idle poller shows live values before any run.
  QTRY_VERIFY_WITH_TIMEOUT(tester->value_text().contains(QStringLiteral("N")), 5000);
}

void WindowRunTest::demo_run_fills_the_step_table_from_the_engine() {
  auto w = make_window();
  connect_simulated_lab(*w);
  QVERIFY(!w->actions().start->isEnabled());  // no protocol yet
  next_file_ = write(QStringLiteral("three.toml"), short_protocol("0.5, 1.0, 1.5"));
  w->actions().open_protocol->trigger();
  QVERIFY(w->protocol().has_value());
  QCOMPARE(w->protocol()->steps.size(), std::size_t{3});
  QVERIFY(w->actions().start->isEnabled());

  QSignalSpy started(w.get(), &MainWindow::run_started);
  QSignalSpy finished(w.get(), &MainWindow::run_finished);
  w->actions().start->trigger();
  QVERIFY(started.wait(20000));
  const qint64 run_id = started.at(0).at(0).toLongLong();
  QVERIFY(finished.wait(50000));
  QVERIFY(finished.at(0).at(0).value<EngineState>() == EngineState::completed);
  QCOMPARE(w->error_count(), 0);

  // The step table holds exactly what the database holds.
  const StepTableModel* steps = w->run_view()->steps();
  db::Reader reader(w->record_database().toStdString());
  const auto compare = reader.compare(run_id);
  QCOMPARE(compare.size(), std::size_t{3});
  QCOMPARE(steps->rowCount(), 3);
  QCOMPARE(steps->predicted_count(), 3);
  const auto load = reader.channel(run_id, "load");
  QVERIFY(load.has_value());
  for (std::size_t i = 0; i < compare.size(); ++i) {
    const StepRow& r = steps->rows()[i];
    const db::CompareRow& c = compare[i];
    QCOMPARE(r.step, c.step.index);
    QCOMPARE(r.displacement_mm, c.step.target_displacement_mm);
    QCOMPARE(r.nominal_strain, c.step.nominal_strain);
    QCOMPARE(r.measured_T, c.step.measured_transmission);
    QVERIFY(r.measured_T > 0.0 && r.measured_T < 1.0);
    QVERIFY(std::abs(r.load_N - c.step.stats_for(load->id)->mean) <=
            1e-9 * std::max(1.0, std::abs(r.load_N)));
    QVERIFY(c.prediction.has_value());
    QCOMPARE(*r.predicted_T, c.prediction->T);
    QCOMPARE(*r.predicted_T_stderr, c.prediction->T_stderr);
    QCOMPARE(*r.predicted_T, 0.9 * r.measured_T + 0.01);
    // The latency the run measured, as stored, and shown in its column.
    QVERIFY(r.prediction_latency_s.has_value());
    QCOMPARE(*r.prediction_latency_s, c.prediction->latency_s);
    QVERIFY(*r.prediction_latency_s >= 0.0);
    QCOMPARE(steps->data(steps->index(static_cast<int>(i), StepTableModel::kLatency)).toString(),
             QString::number(c.prediction->latency_s, 'f', 2));
  }
  // Deeper steps carry more load.
  QVERIFY(steps->rows()[2].load_N > steps->rows()[0].load_N);
  // The comparison chart has every measured and simulated point, with error bars.
  QCOMPARE(w->run_view()->comparison()->measured_points().size(), std::size_t{3});
  QCOMPARE(w->run_view()->comparison()->error_bars().size(), std::size_t{3});
  // Live charts received the streams.
  QVERIFY(w->run_view()->load_chart()->samples_seen() > 100);
  QVERIFY(w->run_view()->power_chart()->samples_seen() > 10);

  // The run browser opens the same file read-only and shows the same rows.
  next_file_ = w->record_database();
  QSignalSpy opened(w->browser_backend(), &RunBrowserBackend::database_opened);
  w->actions().open_database->trigger();
  QVERIFY(opened.wait(10000));
  QCOMPARE(w->browser_view()->run_count(), 1);
  QSignalSpy loaded(w->browser_backend(), &RunBrowserBackend::run_loaded);
  w->browser_view()->select_run(run_id);
  QVERIFY(loaded.wait(10000));
  QCOMPARE(w->browser_view()->steps()->rowCount(), 3);
  for (int i = 0; i < 3; ++i) {
    QCOMPARE(w->browser_view()->steps()->rows()[static_cast<std::size_t>(i)].predicted_T,
             steps->rows()[static_cast<std::size_t>(i)].predicted_T);
  }
  QVERIFY(w->actions().export_csv->isEnabled());
  next_file_ = dir_->filePath(QStringLiteral("run.csv"));
  QSignalSpy exported(w->browser_backend(), &RunBrowserBackend::exported);
  w->actions().export_csv->trigger();
  QVERIFY(exported.wait(10000));
  QVERIFY(QFile::exists(next_file_));

  // The lab is handed back to the panels after the run.
  QTRY_VERIFY_WITH_TIMEOUT(w->actions().start->isEnabled(), 10000);
}

void WindowRunTest::pause_resume_abort_reach_the_engine() {
  auto w = make_window();
  connect_simulated_lab(*w);
  QVERIFY(w->load_protocol_text(short_protocol(), QStringLiteral("t")));
  QSignalSpy started(w.get(), &MainWindow::run_started);
  QSignalSpy finished(w.get(), &MainWindow::run_finished);
  w->actions().start->trigger();
  QVERIFY(started.wait(20000));
  acquisition::Engine* engine = w->run_backend()->engine();
  QVERIFY(engine);
  QTRY_VERIFY_WITH_TIMEOUT(w->actions().pause->isEnabled(), 5000);

  w->actions().pause->trigger();
  QTRY_VERIFY_WITH_TIMEOUT(engine->state() == EngineState::paused, 10000);
  QTRY_VERIFY_WITH_TIMEOUT(w->actions().resume->isEnabled(), 5000);
  QVERIFY(!w->actions().pause->isEnabled());
  QVERIFY(w->run_view()->state_text().contains(QStringLiteral("paused")));

  w->actions().resume->trigger();
  QTRY_VERIFY_WITH_TIMEOUT(engine->state() != EngineState::paused, 10000);

  w->actions().abort->trigger();
  QVERIFY(finished.wait(30000));
  QVERIFY(finished.at(0).at(0).value<EngineState>() == EngineState::aborted);
  db::Reader reader(w->record_database().toStdString());
  QVERIFY(reader.run(started.at(0).at(0).toLongLong()).status == db::RunStatus::aborted);
  QVERIFY(w->run_view()->events()->count_containing(QStringLiteral("abort")) > 0);
}

void WindowRunTest::bad_files_show_an_error_dialog() {
  auto w = make_window();
  // A file that is not a database at all.
  next_file_ = write(QStringLiteral("junk.tocdlab"), QString(5000, QLatin1Char('j')));
  w->actions().open_database->trigger();
  QTRY_COMPARE_WITH_TIMEOUT(w->error_count(), 1, 10000);
  auto* box = w->findChild<QMessageBox*>(QStringLiteral("error_dialog"));
  QVERIFY(box);
  QVERIFY(box->isVisible());
  box->close();
  // A protocol with a bad value names the line and key.
  next_file_ = write(QStringLiteral("bad.toml"),
                     short_protocol().replace(QStringLiteral("hold_s = 0.5"), QStringLiteral("hold_s = -1")));
  w->actions().open_protocol->trigger();
  QCOMPARE(w->error_count(), 2);
  QVERIFY2(w->last_error().contains(QStringLiteral("hold_s")), qPrintable(w->last_error()));
  QVERIFY(!w->protocol().has_value());
  // A lab TOML that does not parse.
  next_file_ = write(QStringLiteral("lab.toml"), QStringLiteral("[tester\nhost = 1"));
  w->actions().open_lab->trigger();
  QTRY_COMPARE_WITH_TIMEOUT(w->error_count(), 3, 10000);
  QVERIFY(!w->lab_backend()->is_connected());
}

QTEST_MAIN(WindowRunTest)
#include "test_window_run.moc"

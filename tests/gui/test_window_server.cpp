// The window's Data > Open server database: a run pushed to a PostgreSQL server is listed and
// loaded as from its file, and a server that is down is an error dialog, not a hang. Runs
// inside tests/db/with_pg_server (a throw-away server; the test creates database `gui`).
#include <QAction>
#include <QMessageBox>
#include <QSettings>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <cstdlib>

#include "backend_db.hpp"
#include "browser_view.hpp"
#include "gui_settings.hpp"
#include "main_window.hpp"
#include "step_table_model.hpp"
#include "test_settings.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/push.hpp"
#include "tocd/db/reader.hpp"

using namespace tocd;
using namespace tocd::gui;

class WindowServerTest : public QObject {
  Q_OBJECT

 private slots:
  void opens_a_pushed_run_from_the_server();
  void a_server_that_is_down_is_an_error();

 private:
  std::unique_ptr<MainWindow> make_window(const QString& answer);
  QTemporaryDir dir_;
};

std::unique_ptr<MainWindow> WindowServerTest::make_window(const QString& answer) {
  auto w = std::make_unique<MainWindow>(testing::settings_in(dir_));
  w->set_file_chooser([answer](MainWindow::FileRequest r) {
    return r == MainWindow::FileRequest::open_server ? answer : QString();
  });
  w->show();
  return w;
}

void WindowServerTest::opens_a_pushed_run_from_the_server() {
  QVERIFY2(std::getenv("PGPORT"), "run through tests/db/with_pg_server");
  QCOMPARE(std::system("createdb gui"), 0);
  const std::string file = dir_.filePath(QStringLiteral("rig.tocdlab")).toStdString();
  {
    db::Database database(file);
    const auto run = database.create_run({});
    const auto load = database.add_channel({0, run.id, "load", "N", 0, 1000.0});
    database.add_event({0, run.id, run.monotonic_anchor_ns + 5, "state", "running", -1, ""});
    for (int k = 0; k < 2; ++k) {
      db::StepRecord s;
      s.run_id = run.id;
      s.index = k;
      s.target_displacement_mm = 0.5 * (k + 1);
      s.measured_transmission = 0.3 + 0.05 * k;
      s.channels = {{load.id, 1.0 + k, 0.01, 1000}};
      database.add_step(s);
    }
    database.set_run_status(run.id, db::RunStatus::completed);
  }
  const std::string server = "postgresql:///gui";
  const auto pushed = db::push_runs(file, server);
  QCOMPARE(pushed.size(), std::size_t{1});

  auto w = make_window(QString::fromStdString(server));
  QSignalSpy opened(w->browser_backend(), &RunBrowserBackend::database_opened);
  w->actions().open_server->trigger();
  QVERIFY(opened.wait(10000));
  QCOMPARE(w->browser_view()->run_count(), 1);
  QSignalSpy loaded(w->browser_backend(), &RunBrowserBackend::run_loaded);
  w->browser_view()->select_run(pushed[0].server_id);
  QVERIFY(loaded.wait(10000));
  const auto compare = db::Reader(server).compare(pushed[0].server_id);
  QCOMPARE(w->browser_view()->steps()->rowCount(), 2);
  for (int i = 0; i < 2; ++i)
    QCOMPARE(w->browser_view()->steps()->rows()[static_cast<std::size_t>(i)].measured_T,
             compare[static_cast<std::size_t>(i)].step.measured_transmission);
}

void WindowServerTest::a_server_that_is_down_is_an_error() {
  auto w = make_window(QStringLiteral("postgresql://127.0.0.1:1/gui"));
  QSignalSpy failed(w->browser_backend(), &RunBrowserBackend::failed);
  w->actions().open_server->trigger();
  QVERIFY(failed.wait(15000));
  QVERIFY(failed.at(0).at(1).toString().contains(QStringLiteral("cannot connect to PostgreSQL")));
}

QTEST_MAIN(WindowServerTest)
#include "test_window_server.moc"

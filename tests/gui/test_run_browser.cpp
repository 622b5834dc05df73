#include <QFile>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <cmath>

#include "backend_db.hpp"
#include "predicted_run.hpp"
#include "step_table_model.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/writer.hpp"
#include "tocd/test/files.hpp"

using namespace tocd;
using tocd::gui::RunBrowserBackend;
using tocd::gui::RunDetails;
using tocd::gui::RunListing;
using tocd::gui::StepTableModel;
using tocd::test::read_file;
using tocd::test::write_file;

namespace {

// What the backend answered when asked to open a database.
struct OpenAnswer {
  int opened = 0, failed = 0;  ///< database_opened and failed signals received
  QVector<RunListing> runs;    ///< as database_opened listed them
  QString failure;             ///< the failed signal's message
};

// Opens the database at `path` in `backend` and waits up to 10 s for its answer.
[[nodiscard]] OpenAnswer open_in(RunBrowserBackend& backend, const QString& path) {
  QSignalSpy opened(&backend, &RunBrowserBackend::database_opened);
  QSignalSpy failed(&backend, &RunBrowserBackend::failed);
  backend.open_database(path);
  if (!QTest::qWaitFor([&] { return !opened.isEmpty() || !failed.isEmpty(); }, 10000))
    return {};  // no answer
  OpenAnswer a{static_cast<int>(opened.count()), static_cast<int>(failed.count()), {}, {}};
  if (!opened.isEmpty()) a.runs = opened.at(0).at(1).value<QVector<RunListing>>();
  if (!failed.isEmpty()) a.failure = failed.at(0).at(1).toString();
  return a;
}

}  // namespace

class RunBrowserTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase();
  void lists_and_loads_a_run();
  void exports_csv();
  void refuses_corrupt_and_foreign_files();
  void fits_the_law_of_a_run_on_its_own_worker();
  void a_fit_that_cannot_be_made_is_reported();
  void an_identification_that_cannot_be_made_is_reported();
  void computes_a_water_time_course_on_the_long_job_worker();
  void a_water_course_that_cannot_be_made_is_reported();

 private:
  /// fit_law(run_id_, material) on the small run ends in failed(), naming the run and
  /// `named`, with nothing fitted, and the backend free for the next job.
  void expect_fit_failure(const QString& material, const QString& named, int wait_ms);

  QTemporaryDir dir_;
  QString db_path_;
  std::int64_t run_id_ = 0;
};

// A small completed run: 3 steps with load statistics, predictions for steps 0 (made by the
// run, with its latency) and 2 (made outside it, none), 1 kHz paired displacement/load samples
// and an event.
void RunBrowserTest::initTestCase() {
  QVERIFY(dir_.isValid());
  db_path_ = dir_.filePath(QStringLiteral("lab.tocdlab"));
  auto database = db::Database::open(db_path_.toStdString());
  db::NewRun nr;
  nr.name = "browser test";
  nr.operator_name = "tester";
  const db::RunRecord run = database.create_run(nr);
  run_id_ = run.id;
  const auto disp = database.add_channel({0, run.id, "displacement", "mm", 0, 1000.0});
  const auto load = database.add_channel({0, run.id, "load", "N", 0, 1000.0});
  {
    db::Writer writer(database);
    for (int i = 0; i < 3000; ++i) {
      const std::int64_t t = run.monotonic_anchor_ns + i * 1000000LL;
      const double d = 0.0005 * i;
      writer.enqueue(db::Sample{disp.id, t, d});
      writer.enqueue(db::Sample{load.id, t, 4.0 * d * d});
    }
    writer.flush();
  }
  for (int k = 0; k < 3; ++k) {
    db::StepRecord s;
    s.run_id = run.id;
    s.index = k;
    s.target_displacement_mm = 0.5 * (k + 1);
    s.nominal_strain = s.target_displacement_mm / 2.5;
    s.measured_transmission = 0.3 + 0.05 * k;
    s.channels = {{disp.id, s.target_displacement_mm, 0.001, 1000}, {load.id, 1.0 + k, 0.01, 1000}};
    database.add_step(s);
  }
  for (int k : {0, 2}) {
    db::PredictionRecord p;
    p.run_id = run.id;
    p.step_index = k;
    p.T = 0.32 + 0.05 * k;
    p.T_stderr = 0.004;
    p.config_json = "{}";
    if (k == 0) p.latency_s = 2.5;
    database.add_prediction(p);
  }
  db::EventRecord e;
  e.run_id = run.id;
  e.t_ns = run.monotonic_anchor_ns + 5;
  e.kind = "state";
  e.message = "running";
  database.add_event(e);
  database.set_run_status(run.id, db::RunStatus::completed);
}

void RunBrowserTest::lists_and_loads_a_run() {
  RunBrowserBackend backend;
  const OpenAnswer answer = open_in(backend, db_path_);
  QCOMPARE(answer.opened, 1);
  QCOMPARE(answer.failed, 0);
  const auto& runs = answer.runs;
  QCOMPARE(runs.size(), 1);
  QCOMPARE(runs[0].id, run_id_);
  QCOMPARE(runs[0].status, QStringLiteral("completed"));
  QCOMPARE(runs[0].steps, 3);
  QCOMPARE(runs[0].predictions, 2);

  QSignalSpy loaded(&backend, &RunBrowserBackend::run_loaded);
  backend.load_run(run_id_);
  QVERIFY(loaded.wait(10000));
  const auto details = loaded.at(0).at(0).value<RunDetails>();
  // Every row equals what the database holds (read independently here).
  db::Reader reader(db_path_.toStdString());
  const auto compare = reader.compare(run_id_);
  QCOMPARE(details.rows.size(), compare.size());
  for (std::size_t i = 0; i < compare.size(); ++i) {
    const auto& r = details.rows[i];
    QCOMPARE(r.step, compare[i].step.index);
    QCOMPARE(r.displacement_mm, compare[i].step.target_displacement_mm);
    QCOMPARE(r.measured_T, compare[i].step.measured_transmission);
    QCOMPARE(r.load_N, 1.0 + static_cast<double>(i));
    QCOMPARE(r.predicted_T.has_value(), compare[i].prediction.has_value());
    if (r.predicted_T) {
      QCOMPARE(*r.predicted_T, compare[i].prediction->T);
      QCOMPARE(*r.predicted_T_stderr, compare[i].prediction->T_stderr);
    }
  }
  // The step table's latency column: the stored latency, empty for a prediction without one,
  // pending for a step without a prediction.
  StepTableModel table;
  table.set_rows(details.rows);
  const auto latency = [&](int row) { return table.data(table.index(row, StepTableModel::kLatency)); };
  QCOMPARE(latency(0).toString(), QStringLiteral("2.50"));
  QCOMPARE(table.data(table.index(0, StepTableModel::kLatency), Qt::UserRole).toDouble(), 2.5);
  QCOMPARE(latency(1).toString(), QStringLiteral("pending"));
  QVERIFY(!latency(2).isValid());
  QCOMPARE(details.events.size(), std::size_t{1});
  QCOMPARE(details.events[0].message, QStringLiteral("running"));
  QCOMPARE(details.series.size(), std::size_t{2});
  QVERIFY(details.series[0].points.size() <= 2 * 2000 + 2);
  // Paired load vs displacement follows load = 4 d^2.
  QVERIFY(!details.load_vs_displacement.empty());
  for (const QPointF& p : details.load_vs_displacement) {
    QVERIFY(std::abs(p.y() - 4.0 * p.x() * p.x()) < 1e-12);
  }
}

void RunBrowserTest::exports_csv() {
  RunBrowserBackend backend;
  QVERIFY(open_in(backend, db_path_).opened);
  QSignalSpy exported(&backend, &RunBrowserBackend::exported);
  const QString csv = dir_.filePath(QStringLiteral("run.csv"));
  backend.export_csv(run_id_, csv);
  QVERIFY(exported.wait(10000));
  const QList<QByteArray> lines =
      QByteArray::fromStdString(read_file(csv.toStdString())).trimmed().split('\n');
  QCOMPARE(lines.size(), 4);  // header + 3 steps
  QVERIFY(lines[0].contains("measured_T"));
  QVERIFY(lines[1].contains("0.32"));
  // An export into a folder that does not exist fails with a message.
  QSignalSpy failed(&backend, &RunBrowserBackend::failed);
  backend.export_csv(run_id_, dir_.filePath(QStringLiteral("no/such/dir/run.csv")));
  QVERIFY(failed.wait(10000));
}

void RunBrowserTest::refuses_corrupt_and_foreign_files() {
  const QString junk = dir_.filePath(QStringLiteral("junk.tocdlab"));
  const std::string junk_bytes(4096, 'x');
  QVERIFY(write_file(junk.toStdString(), junk_bytes));
  const QString missing = dir_.filePath(QStringLiteral("missing.tocdlab"));
  for (const QString& path : {junk, missing}) {
    RunBrowserBackend backend;
    const OpenAnswer answer = open_in(backend, path);
    QCOMPARE(answer.failed, 1);
    QCOMPARE(answer.opened, 0);
    QVERIFY(!backend.is_open());
    QVERIFY(!answer.failure.isEmpty());
  }
  // The refused file is left as it was.
  QCOMPARE(read_file(junk.toStdString()), junk_bytes);
  QVERIFY(!QFile::exists(missing));
}

// The published law from a fit file re-makes the stored predictions exactly (same configs, same
// seeds): the view's points are the database's T, with a band of zero width.
void RunBrowserTest::fits_the_law_of_a_run_on_its_own_worker() {
  const QString path = dir_.filePath(QStringLiteral("predicted.tocdlab"));
  const auto run = analysis::testing::write_predicted_run(path.toStdString());
  const QString fit = dir_.filePath(QStringLiteral("fit.json"));
  QVERIFY(write_file(fit.toStdString(), analysis::testing::scaled_fit_json(1.0, {1.0})));
  RunBrowserBackend backend;
  QVERIFY(open_in(backend, path).opened);
  QSignalSpy fitted(&backend, &RunBrowserBackend::law_fitted);
  QSignalSpy progress(&backend, &RunBrowserBackend::fit_progress);
  QSignalSpy failed(&backend, &RunBrowserBackend::failed);
  backend.fit_law(run, fit);
  QVERIFY(backend.fitting());
  // Browsing goes on while the fit runs.
  QSignalSpy loaded(&backend, &RunBrowserBackend::run_loaded);
  backend.load_run(run);
  QVERIFY(loaded.wait(20000));
  QVERIFY(fitted.wait(300000));
  QCOMPARE(failed.count(), 0);
  QVERIFY(!backend.fitting());
  QCOMPARE(progress.count(), 2);  // one line per re-predicted step
  const auto view = fitted.at(0).at(0).value<gui::FittedLawView>();
  QCOMPARE(view.run_id, run);
  QVERIFY(view.summary.contains(QStringLiteral("1 confidence laws")));
  db::Reader reader(path.toStdString());
  const auto compare = reader.compare(run);
  QCOMPARE(view.points.size(), compare.size());
  for (std::size_t i = 0; i < compare.size(); ++i) {
    const auto& p = view.points[i];
    QVERIFY(compare[i].prediction.has_value());
    QCOMPARE(p.step, compare[i].step.index);
    QCOMPARE(p.nominal_strain, compare[i].step.nominal_strain);
    QCOMPARE(p.T, compare[i].prediction->T);
    QCOMPARE(p.T_stderr, compare[i].prediction->T_stderr);
    QCOMPARE(p.band_lo, p.T);
    QCOMPARE(p.band_hi, p.T);
  }
}

void RunBrowserTest::expect_fit_failure(const QString& material, const QString& named, int wait_ms) {
  RunBrowserBackend backend;
  QVERIFY(open_in(backend, db_path_).opened);
  QSignalSpy failed(&backend, &RunBrowserBackend::failed);
  QSignalSpy fitted(&backend, &RunBrowserBackend::law_fitted);
  backend.fit_law(run_id_, material);
  QVERIFY(failed.wait(wait_ms));
  QCOMPARE(fitted.count(), 0);
  QVERIFY(failed.at(0).at(0).toString().contains(QString::number(run_id_)));
  QVERIFY2(failed.at(0).at(1).toString().contains(named), qPrintable(failed.at(0).at(1).toString()));
  QVERIFY(!backend.fitting());
}

// A fit file that is not there: the fit ends in failed(), naming the run and the file, and the
// backend is free for the next one.
void RunBrowserTest::a_fit_that_cannot_be_made_is_reported() {
  expect_fit_failure(dir_.filePath(QStringLiteral("no_such_fit.json")), QStringLiteral("no_such_fit.json"),
                     20000);
}

// "Identify the sample" on a run the identification cannot model (this small run records no
// sample thickness, nor any transmission): the failure names the run and what it lacks, rather
// than drawing a T that was never identified, and the worker is free again.
void RunBrowserTest::an_identification_that_cannot_be_made_is_reported() {
  expect_fit_failure(QStringLiteral("identified"), QStringLiteral("thickness"), 120000);
}

// A pin run as the engine records it: on the surface, then 0.25 mm; displacement at 100 Hz,
// power at 10 Hz, a short recording window per step (one predicted point each). Real FE,
// meshes and Monte Carlo with few photons.
void RunBrowserTest::computes_a_water_time_course_on_the_long_job_worker() {
  const QString path = dir_.filePath(QStringLiteral("water.tocdlab"));
  constexpr double P0 = 1e-3;
  std::int64_t run_id = 0, t0 = 0;
  {
    auto database = db::Database::open(path.toStdString());
    db::SampleRecord sample;
    sample.thickness_mm = 2.5;
    db::NewRun nr;
    nr.name = "water";
    nr.baseline_power_W = P0;
    nr.sample_id = database.add_sample(sample);
    const db::RunRecord run = database.create_run(nr);
    run_id = run.id;
    t0 = run.monotonic_anchor_ns;
    const auto disp = database.add_channel({0, run.id, "displacement", "mm", 0, 100.0});
    const auto power = database.add_channel({0, run.id, "power", "W", 0, 10.0});
    db::Writer writer(database);
    for (int i = 0; i <= 600; ++i) {
      const double t = 0.01 * i;
      writer.enqueue(db::Sample{disp.id, t0 + i * 10'000'000LL, t < 2 ? 0.0 : std::min(0.25, 0.5 * (t - 2))});
    }
    for (int i = 0; i <= 60; ++i)
      writer.enqueue(db::Sample{power.id, t0 + i * 100'000'000LL, P0 * (0.2 + 0.001 * i)});
    writer.flush();
    for (int k = 0; k < 2; ++k) {
      db::StepRecord s;
      s.run_id = run.id;
      s.index = k;
      s.target_displacement_mm = 0.25 * k;
      s.recorded_from_t_ns = t0 + (k == 0 ? 500'000'000LL : 4'000'000'000LL);
      s.recorded_to_t_ns = s.recorded_from_t_ns + 1'500'000'000LL;
      database.add_step(s);
    }
  }
  RunBrowserBackend backend;
  QVERIFY(open_in(backend, path).opened);
  QSignalSpy ready(&backend, &RunBrowserBackend::water_course_ready);
  QSignalSpy progress(&backend, &RunBrowserBackend::water_progress);
  QSignalSpy failed(&backend, &RunBrowserBackend::failed);
  backend.water_course(run_id, 1000);
  QVERIFY(backend.fitting());
  QVERIFY(ready.wait(300000));
  QCOMPARE(failed.count(), 0);
  QVERIFY(!backend.fitting());
  QVERIFY(progress.count() >= 2);
  const auto v = ready.at(0).at(0).value<gui::WaterCourseView>();
  QCOMPARE(v.run_id, run_id);
  QCOMPARE(v.steps.size(), std::size_t{2});
  for (const auto& s : v.steps) {
    // The measured line is every stored power sample of the window (16 at 10 Hz in 1.5 s), as T.
    QCOMPARE(s.measured.size(), std::size_t{16});
    for (const QPointF& m : s.measured) {
      QVERIFY(m.x() >= s.window_from_s - 1e-9 && m.x() <= s.window_to_s + 1e-9);
      const int i = static_cast<int>(std::lround(m.x() * 10));
      QVERIFY(std::abs(m.y() - (0.2 + 0.001 * i)) < 1e-12);
    }
    QCOMPARE(s.points.size(), std::size_t{1});
    const auto& p = s.points[0];
    QVERIFY2(p.computed, qPrintable(p.failure));
    QVERIFY(p.t_s > s.window_from_s && p.t_s < s.window_to_s);
    QVERIFY(std::isfinite(p.T) && p.T_stderr > 0);
  }
}

// A run without a pin record: failed() names the run and what is missing; the worker is free.
void RunBrowserTest::a_water_course_that_cannot_be_made_is_reported() {
  RunBrowserBackend backend;
  QVERIFY(open_in(backend, db_path_).opened);
  QSignalSpy failed(&backend, &RunBrowserBackend::failed);
  backend.water_course(run_id_, 1000);
  QVERIFY(failed.wait(20000));
  QVERIFY(failed.at(0).at(0).toString().contains(QString::number(run_id_)));
  QVERIFY(failed.at(0).at(1).toString().contains(QStringLiteral("no power channel")));
  QVERIFY(!backend.fitting());
}

QTEST_GUILESS_MAIN(RunBrowserTest)
#include "test_run_browser.moc"

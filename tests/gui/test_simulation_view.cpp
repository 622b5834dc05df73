// The simulation view driven through its action: one real prediction with a small photon
// budget, its row in the result table and both fluence slices on one colour scale.
#include <QAction>
#include <QProgressBar>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <cmath>

#include "backend_study.hpp"
#include "colour_map.hpp"
#include "main_window.hpp"
#include "simulation_view.hpp"
#include "test_settings.hpp"

using namespace tocd::gui;

class SimulationViewTest : public QObject {
  Q_OBJECT

 private slots:
  void one_prediction_fills_table_and_maps();
};

void SimulationViewTest::one_prediction_fills_table_and_maps() {
  if (!StudyBackend::available()) QSKIP("this build has no simulator");
  QTemporaryDir dir;
  MainWindow w(testing::settings_in(dir));
  w.show();
  SimulationView* view = w.simulation_view();
  view->set_photons(2000);
  QSignalSpy finished(w.study_backend(), &StudyBackend::finished);
  QSignalSpy failed(w.study_backend(), &StudyBackend::failed);
  QVERIFY(w.actions().predict->isEnabled());
  w.actions().predict->trigger();
  QVERIFY(!w.actions().predict->isEnabled());  // one simulation at a time
  QVERIFY(finished.wait(150000));
  QCOMPARE(failed.count(), 0);
  QCOMPARE(view->row_count(), 1);
  QCOMPARE(view->progress_bar()->value(), 1);
  QTRY_VERIFY(w.actions().predict->isEnabled());
  // Left: pin-tip height, right: pin axis, of the same simulation; one shared log scale.
  const FluenceMapPair* maps = view->maps();
  QVERIFY(!maps->grid(0).empty());
  QVERIFY(!maps->grid(1).empty());
  QCOMPARE(maps->grid(1).y_label, QStringLiteral("z (mm)"));
  const auto [lo, hi] = maps->log10_range();
  QVERIFY(hi > lo);
  QVERIFY(std::isfinite(lo) && std::isfinite(hi));
}

QTEST_MAIN(SimulationViewTest)
#include "test_simulation_view.moc"

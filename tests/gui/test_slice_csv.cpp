#include <QTest>
#include <cmath>

#include "slice_csv.hpp"

using tocd::gui::parse_slice_csv;
using tocd::gui::ScalarGrid;
using tocd::gui::SliceCsvError;

class SliceCsvTest : public QObject {
  Q_OBJECT

 private slots:
  void reads_a_vertical_slice_in_any_order();
  void reads_a_horizontal_slice();
  void rejects_bad_files();
};

void SliceCsvTest::reads_a_vertical_slice_in_any_order() {
  // x-z plane at y = 0: 3 x values, 2 z values, rows shuffled, one point outside the mesh.
  const QString text = QStringLiteral(
      "x_mm,y_mm,z_mm,region,fluence,fluence_se\n"
      "0.1,0,0.5,4,6,0.1\n"
      "-0.1,0,0.5,4,4,0.1\n"
      "-0.1,0,0.25,4,1,0.1\n"
      "0,0,0.25,4,2,0.1\n"
      "0.1,0,0.25,0,,\n"
      "0,0,0.5,4,5,0.1\n");
  const ScalarGrid g = parse_slice_csv(text, QStringLiteral("v.csv"));
  QCOMPARE(g.nx, 3);
  QCOMPARE(g.ny, 2);
  QCOMPARE(g.x_label, QStringLiteral("x (mm)"));
  QCOMPARE(g.y_label, QStringLiteral("z (mm)"));
  QVERIFY(std::abs(g.x_min - (-0.15)) < 1e-12 && std::abs(g.x_max - 0.15) < 1e-12);
  QVERIFY(std::abs(g.y_min - 0.125) < 1e-12 && std::abs(g.y_max - 0.625) < 1e-12);
  QCOMPARE(g.at(0, 0), 1.0);
  QCOMPARE(g.at(1, 0), 2.0);
  QVERIFY(std::isnan(g.at(2, 0)));
  QCOMPARE(g.at(0, 1), 4.0);
  QCOMPARE(g.at(2, 1), 6.0);
}

void SliceCsvTest::reads_a_horizontal_slice() {
  QString text = QStringLiteral("x_mm,y_mm,z_mm,region,fluence,fluence_se\n");
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 5; ++i)
      text += QStringLiteral("%1,%2,0.9,4,%3,0\n").arg(i * 0.05).arg(j * 0.05 - 0.1).arg(10 * j + i);
  const ScalarGrid g = parse_slice_csv(text, QStringLiteral("h.csv"));
  QCOMPARE(g.nx, 5);
  QCOMPARE(g.ny, 4);
  QCOMPARE(g.y_label, QStringLiteral("y (mm)"));
  QCOMPARE(g.at(3, 2), 23.0);
}

void SliceCsvTest::rejects_bad_files() {
  const auto throws_with = [](const QString& text, const QString& needle) {
    try {
      parse_slice_csv(text, QStringLiteral("bad.csv"));
    } catch (const SliceCsvError& e) {
      const QString m = QString::fromUtf8(e.what());
      return m.startsWith(QStringLiteral("bad.csv:")) && m.contains(needle);
    }
    return false;
  };
  QVERIFY(throws_with(QString(), QStringLiteral("empty")));
  QVERIFY(throws_with(QStringLiteral("a,b,c\n1,2,3\n"), QStringLiteral("x_mm")));
  QVERIFY(throws_with(QStringLiteral("x_mm,y_mm,z_mm,fluence\n"), QStringLiteral("no data")));
  QVERIFY(throws_with(QStringLiteral("x_mm,y_mm,z_mm,fluence\n1,2,3\n"), QStringLiteral(":2:")));
  QVERIFY(throws_with(QStringLiteral("x_mm,y_mm,z_mm,fluence\n1,2,q,4\n"), QStringLiteral("z_mm")));
  QVERIFY(throws_with(QStringLiteral("x_mm,y_mm,z_mm,fluence\n0,0,0,1\n1,1,1,1\n0,1,1,2\n"),
                      QStringLiteral("3 coordinates vary")));
  QVERIFY(throws_with(QStringLiteral("x_mm,y_mm,z_mm,fluence\n0,0,0,1\n1,0,0,1\n0,0,1,2\n"),
                      QStringLiteral("grid")));
  QVERIFY_THROWS_EXCEPTION(SliceCsvError, tocd::gui::read_slice_csv(QStringLiteral("/no/such.csv")));
}

QTEST_GUILESS_MAIN(SliceCsvTest)
#include "test_slice_csv.moc"

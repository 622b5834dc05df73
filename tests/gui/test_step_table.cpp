#include <QSignalSpy>
#include <QTest>

#include "step_table_model.hpp"

using tocd::gui::StepRow;
using tocd::gui::StepTableModel;

class StepTableTest : public QObject {
  Q_OBJECT

 private slots:
  void rows_are_ordered_by_step();
  void prediction_fills_in_and_difference_follows();
  void prediction_before_step_is_kept();
  void remeasured_step_keeps_its_prediction();
  void display_text_and_raw_values();
  void latency_column_shows_the_prediction_latency();
};

namespace {
StepRow row(int step, double d, double T) {
  StepRow r;
  r.step = step;
  r.displacement_mm = d;
  r.nominal_strain = d / 2.0;
  r.load_N = 3.0 * d;
  r.measured_T = T;
  return r;
}
}  // namespace

void StepTableTest::rows_are_ordered_by_step() {
  StepTableModel m;
  QSignalSpy inserted(&m, &QAbstractItemModel::rowsInserted);
  m.upsert_measured(row(2, 0.6, 0.3));
  m.upsert_measured(row(0, 0.2, 0.1));
  m.upsert_measured(row(1, 0.4, 0.2));
  QCOMPARE(inserted.count(), 3);
  QCOMPARE(m.rowCount(), 3);
  QCOMPARE(m.columnCount(), static_cast<int>(StepTableModel::kColumnCount));
  for (int i = 0; i < 3; ++i) QCOMPARE(m.rows()[static_cast<std::size_t>(i)].step, i);
}

void StepTableTest::prediction_fills_in_and_difference_follows() {
  StepTableModel m;
  m.upsert_measured(row(0, 0.5, 0.20));
  QCOMPARE(m.predicted_count(), 0);
  QVERIFY(!m.data(m.index(0, StepTableModel::kDifference), Qt::UserRole).isValid());
  QSignalSpy changed(&m, &QAbstractItemModel::dataChanged);
  m.set_prediction(0, 0.25, 0.01);
  QCOMPARE(changed.count(), 1);
  QCOMPARE(m.predicted_count(), 1);
  QCOMPARE(m.data(m.index(0, StepTableModel::kPredictedT), Qt::UserRole).toDouble(), 0.25);
  QCOMPARE(m.data(m.index(0, StepTableModel::kPredictedErr), Qt::UserRole).toDouble(), 0.01);
  // (0.25 - 0.20) / 0.20 = +25 %
  QCOMPARE(m.data(m.index(0, StepTableModel::kDifference), Qt::UserRole).toDouble(), 0.25);
  QCOMPARE(m.data(m.index(0, StepTableModel::kDifference)).toString(), QStringLiteral("25.0 %"));
}

void StepTableTest::prediction_before_step_is_kept() {
  StepTableModel m;
  m.set_prediction(4, 0.5, 0.02);
  QCOMPARE(m.rowCount(), 0);
  m.upsert_measured(row(4, 1.0, 0.4));
  QVERIFY(m.find(4));
  QCOMPARE(*m.find(4)->predicted_T, 0.5);
  QCOMPARE(*m.find(4)->predicted_T_stderr, 0.02);
}

void StepTableTest::remeasured_step_keeps_its_prediction() {
  StepTableModel m;
  m.upsert_measured(row(0, 0.5, 0.2));
  m.set_prediction(0, 0.3, 0.01);
  m.upsert_measured(row(0, 0.5, 0.22));
  QCOMPARE(m.rowCount(), 1);
  QCOMPARE(m.find(0)->measured_T, 0.22);
  QCOMPARE(*m.find(0)->predicted_T, 0.3);
  m.clear();
  QCOMPARE(m.rowCount(), 0);
}

void StepTableTest::display_text_and_raw_values() {
  StepTableModel m;
  m.upsert_measured(row(0, 0.25, 0.123456));
  QCOMPARE(m.data(m.index(0, StepTableModel::kStep)).toString(), QStringLiteral("1"));
  QCOMPARE(m.data(m.index(0, StepTableModel::kDisplacement)).toString(), QStringLiteral("0.250"));
  QCOMPARE(m.data(m.index(0, StepTableModel::kMeasuredT)).toString(), QStringLiteral("0.1235"));
  QCOMPARE(m.data(m.index(0, StepTableModel::kMeasuredT), Qt::UserRole).toDouble(), 0.123456);
  QCOMPARE(m.data(m.index(0, StepTableModel::kPredictedT)).toString(), QStringLiteral("pending"));
  QCOMPARE(m.headerData(StepTableModel::kLoad, Qt::Horizontal).toString(), QStringLiteral("Load (N)"));
  // A zero measured T has no relative difference (no division by zero).
  m.upsert_measured(row(1, 0.5, 0.0));
  m.set_prediction(1, 0.1, 0.01);
  QVERIFY(!m.find(1)->relative_difference());
}

void StepTableTest::latency_column_shows_the_prediction_latency() {
  StepTableModel m;
  QVERIFY(StepTableModel::kLatency > StepTableModel::kPredictedErr);  // after the prediction's columns
  QCOMPARE(m.headerData(StepTableModel::kLatency, Qt::Horizontal).toString(), QStringLiteral("Latency (s)"));
  QVERIFY(m.headerData(StepTableModel::kLatency, Qt::Horizontal, Qt::ToolTipRole)
              .toString()
              .contains(QStringLiteral("recording end")));
  for (int step = 0; step < 2; ++step) m.upsert_measured(row(step, 0.5, 0.2));
  const auto latency = [&](int r, int role) { return m.data(m.index(r, StepTableModel::kLatency), role); };
  QCOMPARE(latency(0, Qt::DisplayRole).toString(), QStringLiteral("pending"));  // no prediction yet
  m.set_prediction(0, 0.25, 0.01, 2.5);
  m.set_prediction(1, 0.25, 0.01);  // made outside its run: no latency
  QCOMPARE(latency(0, Qt::DisplayRole).toString(), QStringLiteral("2.50"));
  QCOMPARE(latency(0, Qt::UserRole).toDouble(), 2.5);
  // Empty, neither "pending" nor 0.
  QVERIFY(!latency(1, Qt::DisplayRole).isValid());
  QVERIFY(!latency(1, Qt::UserRole).isValid());
  // A re-measured step keeps it; a prediction that came before its step brings it along.
  m.upsert_measured(row(0, 0.5, 0.21));
  QCOMPARE(*m.find(0)->prediction_latency_s, 2.5);
  m.set_prediction(4, 0.5, 0.02, 0.75);
  m.upsert_measured(row(4, 1.0, 0.4));
  QCOMPARE(*m.find(4)->prediction_latency_s, 0.75);
}

QTEST_GUILESS_MAIN(StepTableTest)
#include "test_step_table.moc"

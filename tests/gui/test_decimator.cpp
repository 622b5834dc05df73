#include <QTest>
#include <cmath>
#include <numbers>

#include "decimator.hpp"

using tocd::gui::MinMaxDecimator;

class DecimatorTest : public QObject {
  Q_OBJECT

 private slots:
  void keeps_extremes_of_every_bucket();
  void keeps_a_single_sample_spike();
  void bounds_output_and_memory();
  void preserves_arrival_order_within_a_bucket();
  void rejects_bad_arguments();
};

// 10 s of a 1 kHz stream: 5 Hz sine plus deterministic jitter. Every 20 ms bucket's true
// min and max (computed by brute force here) must be among the decimated points.
void DecimatorTest::keeps_extremes_of_every_bucket() {
  const double width = 0.02;
  MinMaxDecimator d(width, 100000);
  std::vector<std::pair<double, double>> samples;
  for (int i = 0; i < 10000; ++i) {
    const double t = i * 1e-3;
    const double y = std::sin(2 * std::numbers::pi * 5 * t) + 0.01 * ((i * 7919) % 13 - 6);
    samples.emplace_back(t, y);
    d.add(t, QPointF(t, y));
  }
  const auto pts = d.points();
  QCOMPARE(d.samples_seen(), std::size_t{10000});
  QVERIFY(pts.size() <= 4 * d.bucket_count());
  QVERIFY(pts.size() < samples.size() / 4);
  for (std::size_t start = 0; start < samples.size();) {
    const auto bucket = static_cast<long long>(std::floor(samples[start].first / width));
    double lo = samples[start].second, hi = lo;
    std::size_t end = start;
    while (end < samples.size() && static_cast<long long>(std::floor(samples[end].first / width)) == bucket) {
      lo = std::min(lo, samples[end].second);
      hi = std::max(hi, samples[end].second);
      ++end;
    }
    bool found_lo = false, found_hi = false;
    for (const QPointF& p : pts) {
      if (std::floor(p.x() / width) != static_cast<double>(bucket)) continue;
      found_lo = found_lo || p.y() == lo;
      found_hi = found_hi || p.y() == hi;
    }
    QVERIFY2(found_lo && found_hi, qPrintable(QStringLiteral("bucket %1").arg(bucket)));
    start = end;
  }
}

void DecimatorTest::keeps_a_single_sample_spike() {
  MinMaxDecimator d(0.1);
  for (int i = 0; i < 5000; ++i) {
    const double t = i * 1e-3;
    d.add(t, QPointF(t, i == 2345 ? 50.0 : 1.0));
  }
  int spikes = 0;
  for (const QPointF& p : d.points()) spikes += p.y() == 50.0 ? 1 : 0;
  QCOMPARE(spikes, 1);
}

void DecimatorTest::bounds_output_and_memory() {
  MinMaxDecimator d(0.01, 50);
  for (int i = 0; i < 100000; ++i) d.add(i * 1e-3, QPointF(i * 1e-3, i % 17));
  QCOMPARE(d.bucket_count(), std::size_t{50});
  const auto pts = d.points();
  QVERIFY(pts.size() <= 200);
  // Only the newest 50 buckets (0.5 s) remain.
  QVERIFY(pts.front().x() >= 99.5 - 1e-9);
  QCOMPARE(pts.back().x(), 99.999);
  d.clear();
  QVERIFY(d.points().empty());
  QCOMPARE(d.samples_seen(), std::size_t{0});
}

void DecimatorTest::preserves_arrival_order_within_a_bucket() {
  MinMaxDecimator d(1.0);
  // Within one bucket: first 5, max 9 early, min -3 late, last 2.
  const double ys[] = {5, 9, 4, 1, -3, 0, 2};
  for (int i = 0; i < 7; ++i) d.add(0.1 * i, QPointF(0.1 * i, ys[i]));
  const auto pts = d.points();
  QCOMPARE(pts.size(), std::size_t{4});
  QCOMPARE(pts[0].y(), 5.0);
  QCOMPARE(pts[1].y(), 9.0);
  QCOMPARE(pts[2].y(), -3.0);
  QCOMPARE(pts[3].y(), 2.0);
  // A lone sample gives a lone point, not four copies.
  MinMaxDecimator single(1.0);
  single.add(0.0, QPointF(0, 1));
  QCOMPARE(single.points().size(), std::size_t{1});
}

void DecimatorTest::rejects_bad_arguments() {
  QVERIFY_THROWS_EXCEPTION(std::invalid_argument, MinMaxDecimator(0.0));
  QVERIFY_THROWS_EXCEPTION(std::invalid_argument, MinMaxDecimator(-1.0));
  QVERIFY_THROWS_EXCEPTION(std::invalid_argument, MinMaxDecimator(std::nan("")));
  QVERIFY_THROWS_EXCEPTION(std::invalid_argument, MinMaxDecimator(1.0, 0));
}

QTEST_GUILESS_MAIN(DecimatorTest)
#include "test_decimator.moc"

#pragma once

#include <QChartView>
#include <QList>
#include <vector>

class QLineSeries;
class QPen;
class QValueAxis;
class QXYSeries;

namespace tocd::gui {

/// What the measured-vs-simulated chart and the hold-course chart share: points on two value
/// axes, with +- error bars drawn one line series per bar (Qt Charts cannot break a line),
/// kept out of the legend, and the bars and points read back for the tests.
class ErrorBarChart : public QChartView {
  Q_OBJECT

 public:
  struct ErrorBar {
    double x, lo, hi;
  };

 protected:
  ErrorBarChart(const QString& x_title, const QString& y_title, QWidget* parent);

  QValueAxis* x_axis() const noexcept { return x_axis_; }
  QValueAxis* y_axis() const noexcept { return y_axis_; }

  /// Puts `series` on the chart, on both axes.
  void add_series(QXYSeries* series);
  /// A new, empty bar drawn with `pen`; it has no legend entry.
  QLineSeries* add_bar(const QPen& pen);
  void remove_bar(QLineSeries* bar);

  /// A bar's points: a stem from lo to hi at x with caps of half width `cap` (points 2 and 3
  /// are the stem, which bars_of reads back).
  static QList<QPointF> bar_points(double x, double lo, double hi, double cap);
  static std::vector<ErrorBar> bars_of(const std::vector<QLineSeries*>& bars);
  static std::vector<QPointF> points_of(const QXYSeries* series);

 private:
  QValueAxis* x_axis_ = nullptr;
  QValueAxis* y_axis_ = nullptr;
};

}  // namespace tocd::gui

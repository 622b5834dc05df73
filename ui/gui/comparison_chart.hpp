#pragma once

#include <QChartView>
#include <map>
#include <vector>

class QLineSeries;
class QScatterSeries;
class QValueAxis;

namespace tocd::gui {

/// Transmission vs nominal strain: measured points, and simulated points with +/- one
/// standard error bars that fill in as predictions arrive. Keyed by step index, so a step
/// re-sent (a resumed run, a reloaded table) replaces its point instead of doubling it.
class ComparisonChart : public QChartView {
  Q_OBJECT

 public:
  explicit ComparisonChart(QWidget* parent = nullptr);

  void set_measured(int step, double nominal_strain, double T);
  void set_predicted(int step, double nominal_strain, double T, double T_stderr);
  void clear();

  struct ErrorBar {
    double x, lo, hi;
  };
  std::vector<QPointF> measured_points() const;
  std::vector<QPointF> predicted_points() const;
  std::vector<ErrorBar> error_bars() const;

 private:
  struct Predicted {
    double x, T, err;
  };
  void rebuild();

  std::map<int, QPointF> measured_;
  std::map<int, Predicted> predicted_;
  QScatterSeries* measured_series_ = nullptr;
  QScatterSeries* predicted_series_ = nullptr;
  std::vector<QLineSeries*> bar_series_;  ///< one per error bar: Qt Charts cannot break a line
  QValueAxis* x_axis_ = nullptr;
  QValueAxis* y_axis_ = nullptr;
};

}  // namespace tocd::gui

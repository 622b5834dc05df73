#pragma once

#include <QChartView>
#include <vector>

#include "water_course_view.hpp"

class QLineSeries;
class QScatterSeries;
class QValueAxis;

namespace tocd::gui {

/// One step's hold over time: the transmission measured at 10 Hz (power / baseline power) as a
/// line, the water-optics prediction T(t) as points with +- one Monte Carlo standard error
/// bars. Points the solver did not reach are left out and named in the title.
class HoldCourseChart : public QChartView {
  Q_OBJECT

 public:
  explicit HoldCourseChart(QWidget* parent = nullptr);

  void show_step(const WaterStepView& step);
  void clear();

  struct ErrorBar {
    double x, lo, hi;
  };
  std::vector<QPointF> measured_points() const;
  std::vector<QPointF> predicted_points() const;
  std::vector<ErrorBar> error_bars() const;
  QString title_text() const;

 private:
  QLineSeries* measured_ = nullptr;
  QScatterSeries* predicted_ = nullptr;
  std::vector<QLineSeries*> bars_;
  QValueAxis* x_axis_ = nullptr;
  QValueAxis* y_axis_ = nullptr;
};

}  // namespace tocd::gui

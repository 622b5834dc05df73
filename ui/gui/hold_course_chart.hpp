#pragma once

#include <vector>

#include "error_bar_chart.hpp"
#include "water_course_view.hpp"

class QLineSeries;
class QScatterSeries;

namespace tocd::gui {

/// One step's hold over time: the transmission measured at 10 Hz (power / baseline power) as a
/// line, the water-optics prediction T(t) as points with +- one Monte Carlo standard error
/// bars. Points the solver did not reach are left out and named in the title.
class HoldCourseChart : public ErrorBarChart {
  Q_OBJECT

 public:
  explicit HoldCourseChart(QWidget* parent = nullptr);

  void show_step(const WaterStepView& step);
  void clear();

  std::vector<QPointF> measured_points() const;
  std::vector<QPointF> predicted_points() const;
  std::vector<ErrorBar> error_bars() const;
  QString title_text() const;

 private:
  QLineSeries* measured_ = nullptr;
  QScatterSeries* predicted_ = nullptr;
  std::vector<QLineSeries*> bars_;
};

}  // namespace tocd::gui

#pragma once

#include <QPointF>
#include <QString>
#include <cstdint>
#include <vector>

namespace tocd::gui {

/// One predicted time point of a hold (analysis::run_water_course): T(t) relative to the
/// glass-only baseline, or the reason it was not computed.
struct WaterPointView {
  double t_s = 0;  ///< on the run's displacement clock
  double measured_T = 0;
  bool computed = false;
  double T = 0, T_stderr = 0;
  QString failure;
};

/// One step's hold: the power-derived T over its recording window (every stored sample / the
/// baseline power) with the predicted points on top.
struct WaterStepView {
  int step = 0;  ///< 0-based
  double displacement_mm = 0, window_from_s = 0, window_to_s = 0;
  std::vector<QPointF> measured;  ///< (t_s, T)
  std::vector<WaterPointView> points;
};

struct WaterCourseView {
  std::int64_t run_id = 0;
  QString summary;  ///< settings and wall time in one line
  std::vector<WaterStepView> steps;
};

}  // namespace tocd::gui

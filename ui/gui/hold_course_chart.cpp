#include "hold_course_chart.hpp"

#include <QChart>
#include <QLineSeries>
#include <QPen>
#include <QScatterSeries>
#include <QValueAxis>
#include <algorithm>
#include <cmath>
#include <limits>

namespace tocd::gui {

HoldCourseChart::HoldCourseChart(QWidget* parent)
    : ErrorBarChart(tr("time in the run (s)"), tr("transmission T"), parent) {
  measured_ = new QLineSeries(chart());
  measured_->setName(tr("measured (power / baseline)"));
  predicted_ = new QScatterSeries(chart());
  predicted_->setName(tr("water optics ± 1 s.e."));
  predicted_->setMarkerShape(QScatterSeries::MarkerShapeRectangle);
  predicted_->setMarkerSize(8);
  add_series(measured_);
  add_series(predicted_);
  clear();
}

void HoldCourseChart::clear() {
  measured_->clear();
  predicted_->clear();
  for (QLineSeries* b : bars_) remove_bar(b);
  bars_.clear();
  chart()->setTitle(tr("Hold: T(t), water optics (no time course computed)"));
  x_axis()->setRange(0, 1);
  y_axis()->setRange(0, 1);
}

void HoldCourseChart::show_step(const WaterStepView& s) {
  clear();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const auto span = [&](double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  };
  QList<QPointF> m;
  for (const QPointF& p : s.measured) {
    m.append(p);
    span(p.y());
  }
  measured_->replace(m);
  int missing = 0;
  QString why;
  // Bars get the scatter's colour so each belongs visibly to its point.
  QPen pen(predicted_->color());
  pen.setWidthF(1.5);
  const double cap = 0.01 * std::max(1e-3, s.window_to_s - s.window_from_s);
  for (const WaterPointView& p : s.points) {
    if (!p.computed) {
      ++missing;
      why = p.failure;
      continue;
    }
    predicted_->append(p.t_s, p.T);
    const double a = p.T - p.T_stderr, b = p.T + p.T_stderr;
    bars_.push_back(add_bar(pen));
    bars_.back()->replace(bar_points(p.t_s, a, b, cap));
    span(a);
    span(b);
  }
  QString title = tr("Step %1 (%2 mm): T over the hold").arg(s.step + 1).arg(s.displacement_mm, 0, 'f', 3);
  if (missing > 0) title += tr("; %1 point(s) not computed: %2").arg(missing).arg(why);
  chart()->setTitle(title);
  x_axis()->setRange(s.window_from_s, std::max(s.window_to_s, s.window_from_s + 1e-3));
  if (std::isfinite(lo)) {
    const double pad = std::max(0.05 * (hi - lo), 0.005);
    y_axis()->setRange(std::max(0.0, lo - pad), hi + pad);
  }
}

std::vector<QPointF> HoldCourseChart::measured_points() const {
  return points_of(measured_);
}

std::vector<QPointF> HoldCourseChart::predicted_points() const {
  return points_of(predicted_);
}

std::vector<HoldCourseChart::ErrorBar> HoldCourseChart::error_bars() const {
  return bars_of(bars_);
}

QString HoldCourseChart::title_text() const {
  return chart()->title();
}

}  // namespace tocd::gui

#include "hold_course_chart.hpp"

#include <QChart>
#include <QLegendMarker>
#include <QLineSeries>
#include <QPen>
#include <QScatterSeries>
#include <QValueAxis>
#include <algorithm>
#include <cmath>
#include <limits>

namespace tocd::gui {

HoldCourseChart::HoldCourseChart(QWidget* parent) : QChartView(parent) {
  auto* chart = new QChart();
  measured_ = new QLineSeries(chart);
  measured_->setName(tr("measured (power / baseline)"));
  predicted_ = new QScatterSeries(chart);
  predicted_->setName(tr("water optics ± 1 s.e."));
  predicted_->setMarkerShape(QScatterSeries::MarkerShapeRectangle);
  predicted_->setMarkerSize(8);
  chart->addSeries(measured_);
  chart->addSeries(predicted_);
  x_axis_ = new QValueAxis(chart);
  y_axis_ = new QValueAxis(chart);
  x_axis_->setTitleText(tr("time in the run (s)"));
  y_axis_->setTitleText(tr("transmission T"));
  chart->addAxis(x_axis_, Qt::AlignBottom);
  chart->addAxis(y_axis_, Qt::AlignLeft);
  for (QXYSeries* s : std::initializer_list<QXYSeries*>{measured_, predicted_}) {
    s->attachAxis(x_axis_);
    s->attachAxis(y_axis_);
  }
  setChart(chart);
  setRenderHint(QPainter::Antialiasing);
  setMinimumSize(300, 220);
  clear();
}

void HoldCourseChart::clear() {
  measured_->clear();
  predicted_->clear();
  for (QLineSeries* b : bars_) {
    chart()->removeSeries(b);
    delete b;
  }
  bars_.clear();
  chart()->setTitle(tr("Hold: T(t), water optics (no time course computed)"));
  x_axis_->setRange(0, 1);
  y_axis_->setRange(0, 1);
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
    auto* bar = new QLineSeries(chart());
    const double a = p.T - p.T_stderr, b = p.T + p.T_stderr;
    bar->append(
        {{p.t_s - cap, a}, {p.t_s + cap, a}, {p.t_s, a}, {p.t_s, b}, {p.t_s - cap, b}, {p.t_s + cap, b}});
    bar->setPen(pen);
    chart()->addSeries(bar);
    bar->attachAxis(x_axis_);
    bar->attachAxis(y_axis_);
    for (QLegendMarker* marker : chart()->legend()->markers(bar)) marker->setVisible(false);
    bars_.push_back(bar);
    span(a);
    span(b);
  }
  QString title = tr("Step %1 (%2 mm): T over the hold").arg(s.step + 1).arg(s.displacement_mm, 0, 'f', 3);
  if (missing > 0) title += tr("; %1 point(s) not computed: %2").arg(missing).arg(why);
  chart()->setTitle(title);
  x_axis_->setRange(s.window_from_s, std::max(s.window_to_s, s.window_from_s + 1e-3));
  if (std::isfinite(lo)) {
    const double pad = std::max(0.05 * (hi - lo), 0.005);
    y_axis_->setRange(std::max(0.0, lo - pad), hi + pad);
  }
}

std::vector<QPointF> HoldCourseChart::measured_points() const {
  const auto pts = measured_->points();
  return {pts.begin(), pts.end()};
}

std::vector<QPointF> HoldCourseChart::predicted_points() const {
  const auto pts = predicted_->points();
  return {pts.begin(), pts.end()};
}

std::vector<HoldCourseChart::ErrorBar> HoldCourseChart::error_bars() const {
  std::vector<ErrorBar> out;
  for (const QLineSeries* s : bars_) {
    const auto pts = s->points();
    out.push_back({pts[2].x(), pts[2].y(), pts[3].y()});
  }
  return out;
}

QString HoldCourseChart::title_text() const {
  return chart()->title();
}

}  // namespace tocd::gui

#include "comparison_chart.hpp"

#include <QChart>
#include <QLegendMarker>
#include <QLineSeries>
#include <QScatterSeries>
#include <QValueAxis>
#include <algorithm>
#include <cmath>

#include "chart_axes.hpp"

namespace tocd::gui {

ComparisonChart::ComparisonChart(QWidget* parent) : QChartView(parent) {
  auto* chart = new QChart();
  chart->setTitle(tr("Transmission: measured vs simulated"));
  measured_series_ = new QScatterSeries(chart);
  measured_series_->setName(tr("measured"));
  measured_series_->setMarkerShape(QScatterSeries::MarkerShapeCircle);
  measured_series_->setMarkerSize(9);
  predicted_series_ = new QScatterSeries(chart);
  predicted_series_->setName(tr("simulated ± 1 s.e."));
  predicted_series_->setMarkerShape(QScatterSeries::MarkerShapeRectangle);
  predicted_series_->setMarkerSize(8);
  chart->addSeries(measured_series_);
  chart->addSeries(predicted_series_);
  x_axis_ = new QValueAxis(chart);
  y_axis_ = new QValueAxis(chart);
  x_axis_->setTitleText(tr("nominal strain"));
  y_axis_->setTitleText(tr("transmission T"));
  x_axis_->setRange(0, 1);
  y_axis_->setRange(0, 1);
  chart->addAxis(x_axis_, Qt::AlignBottom);
  chart->addAxis(y_axis_, Qt::AlignLeft);
  measured_series_->attachAxis(x_axis_);
  measured_series_->attachAxis(y_axis_);
  predicted_series_->attachAxis(x_axis_);
  predicted_series_->attachAxis(y_axis_);
  setChart(chart);
  setRenderHint(QPainter::Antialiasing);
  setMinimumSize(300, 220);
}

void ComparisonChart::set_measured(int step, double nominal_strain, double T) {
  measured_[step] = QPointF(nominal_strain, T);
  rebuild();
}

void ComparisonChart::set_predicted(int step, double nominal_strain, double T, double T_stderr) {
  predicted_[step] = {nominal_strain, T, std::abs(T_stderr)};
  rebuild();
}

void ComparisonChart::clear() {
  measured_.clear();
  predicted_.clear();
  rebuild();
}

void ComparisonChart::rebuild() {
  QList<QPointF> m, p;
  for (const auto& [step, pt] : measured_) m.push_back(pt);
  for (const auto& [step, pr] : predicted_) p.push_back(QPointF(pr.x, pr.T));
  measured_series_->replace(m);
  predicted_series_->replace(p);

  // One series per bar (stem with caps). Reuse what exists, add or drop the difference.
  QChart* c = chart();
  while (bar_series_.size() > predicted_.size()) {
    QLineSeries* s = bar_series_.back();
    bar_series_.pop_back();
    c->removeSeries(s);
    delete s;
  }
  double x_lo = 0, x_hi = 0;
  {
    std::vector<QPointF> all(m.begin(), m.end());
    all.insert(all.end(), p.begin(), p.end());
    double y_lo = 0, y_hi = 0;
    if (bounds(all, x_lo, x_hi, y_lo, y_hi)) {
      for (const auto& [step, pr] : predicted_) {
        y_lo = std::min(y_lo, pr.T - pr.err);
        y_hi = std::max(y_hi, pr.T + pr.err);
      }
      const auto [a, b] = padded_range(x_lo, x_hi, {0.0, 1.0}, 0.08);
      const auto [lo, hi] = padded_range(y_lo, y_hi, {0.0, 1.0}, 0.1);
      x_axis_->setRange(a, b);
      y_axis_->setRange(lo, hi);
      x_lo = a;
      x_hi = b;
    }
  }
  const double cap = 0.01 * std::max(x_hi - x_lo, 1e-6);
  std::size_t k = 0;
  for (const auto& [step, pr] : predicted_) {
    if (k == bar_series_.size()) {
      auto* s = new QLineSeries(c);
      s->setColor(predicted_series_->color());
      c->addSeries(s);
      s->attachAxis(x_axis_);
      s->attachAxis(y_axis_);
      for (QLegendMarker* marker : c->legend()->markers(s)) marker->setVisible(false);
      bar_series_.push_back(s);
    }
    const double lo = pr.T - pr.err, hi = pr.T + pr.err;
    bar_series_[k]->replace(QList<QPointF>{
        {pr.x - cap, lo}, {pr.x + cap, lo}, {pr.x, lo}, {pr.x, hi}, {pr.x - cap, hi}, {pr.x + cap, hi}});
    ++k;
  }
}

std::vector<QPointF> ComparisonChart::measured_points() const {
  const auto pts = measured_series_->points();
  return {pts.begin(), pts.end()};
}

std::vector<QPointF> ComparisonChart::predicted_points() const {
  const auto pts = predicted_series_->points();
  return {pts.begin(), pts.end()};
}

std::vector<ComparisonChart::ErrorBar> ComparisonChart::error_bars() const {
  std::vector<ErrorBar> out;
  for (const QLineSeries* s : bar_series_) {
    const auto pts = s->points();
    out.push_back({pts[2].x(), pts[2].y(), pts[3].y()});
  }
  return out;
}

}  // namespace tocd::gui

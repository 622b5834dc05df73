#include "comparison_chart.hpp"

#include <QChart>
#include <QLegendMarker>
#include <QLineSeries>
#include <QPen>
#include <QScatterSeries>
#include <QValueAxis>
#include <algorithm>
#include <cmath>

#include "chart_axes.hpp"

namespace tocd::gui {

ComparisonChart::ComparisonChart(QWidget* parent)
    : ErrorBarChart(tr("nominal strain"), tr("transmission T"), parent) {
  chart()->setTitle(tr("Transmission: measured vs simulated"));
  measured_series_ = new QScatterSeries(chart());
  measured_series_->setName(tr("measured"));
  measured_series_->setMarkerShape(QScatterSeries::MarkerShapeCircle);
  measured_series_->setMarkerSize(9);
  predicted_series_ = new QScatterSeries(chart());
  predicted_series_->setName(tr("simulated ± 1 s.e."));
  predicted_series_->setMarkerShape(QScatterSeries::MarkerShapeRectangle);
  predicted_series_->setMarkerSize(8);
  fitted_series_ = new QScatterSeries(chart());
  fitted_series_->setName(tr("fitted law ± 1 s.e., model band"));
  fitted_series_->setMarkerShape(QScatterSeries::MarkerShapeTriangle);
  fitted_series_->setMarkerSize(9);
  for (QScatterSeries* s : {measured_series_, predicted_series_, fitted_series_}) add_series(s);
  x_axis()->setRange(0, 1);
  y_axis()->setRange(0, 1);
  // Shown only once a fit has been drawn.
  for (QLegendMarker* marker : chart()->legend()->markers(fitted_series_)) marker->setVisible(false);
}

void ComparisonChart::set_measured(int step, double nominal_strain, double T) {
  measured_[step] = QPointF(nominal_strain, T);
  rebuild();
}

void ComparisonChart::set_predicted(int step, double nominal_strain, double T, double T_stderr) {
  predicted_[step] = {nominal_strain, T, std::abs(T_stderr)};
  rebuild();
}

void ComparisonChart::set_fitted(int step, double nominal_strain, double T, double T_stderr, double band_lo,
                                 double band_hi) {
  fitted_[step] = {nominal_strain, T, std::abs(T_stderr), std::min(band_lo, band_hi),
                   std::max(band_lo, band_hi)};
  rebuild();
}

void ComparisonChart::clear_fitted() {
  fitted_.clear();
  rebuild();
}

void ComparisonChart::clear() {
  measured_.clear();
  predicted_.clear();
  fitted_.clear();
  rebuild();
}

void ComparisonChart::size_bars(std::vector<QLineSeries*>& pool, std::size_t n, const QPen& pen) {
  while (pool.size() > n) {
    remove_bar(pool.back());
    pool.pop_back();
  }
  while (pool.size() < n) pool.push_back(add_bar(pen));
}

void ComparisonChart::rebuild() {
  QList<QPointF> m, p, f;
  for (const auto& [step, pt] : measured_) m.push_back(pt);
  for (const auto& [step, pr] : predicted_) p.push_back(QPointF(pr.x, pr.T));
  for (const auto& [step, ft] : fitted_) f.push_back(QPointF(ft.x, ft.T));
  measured_series_->replace(m);
  predicted_series_->replace(p);
  fitted_series_->replace(f);
  for (QLegendMarker* marker : chart()->legend()->markers(fitted_series_))
    marker->setVisible(!fitted_.empty());

  double x_lo = 0, x_hi = 0;
  {
    std::vector<QPointF> all(m.begin(), m.end());
    all.insert(all.end(), p.begin(), p.end());
    all.insert(all.end(), f.begin(), f.end());
    double y_lo = 0, y_hi = 0;
    if (bounds(all, x_lo, x_hi, y_lo, y_hi)) {
      for (const auto& [step, pr] : predicted_) {
        y_lo = std::min(y_lo, pr.T - pr.err);
        y_hi = std::max(y_hi, pr.T + pr.err);
      }
      for (const auto& [step, ft] : fitted_) {
        y_lo = std::min({y_lo, ft.T - ft.err, ft.lo});
        y_hi = std::max({y_hi, ft.T + ft.err, ft.hi});
      }
      const auto [a, b] = padded_range(x_lo, x_hi, {0.0, 1.0}, 0.08);
      const auto [lo, hi] = padded_range(y_lo, y_hi, {0.0, 1.0}, 0.1);
      x_axis()->setRange(a, b);
      y_axis()->setRange(lo, hi);
      x_lo = a;
      x_hi = b;
    }
  }
  const double cap = 0.01 * std::max(x_hi - x_lo, 1e-6);

  // The model band is drawn behind the fitted point's Monte Carlo bar, wide and pale, so both
  // stay visible.
  QColor band_colour = fitted_series_->color();
  band_colour.setAlpha(70);
  QPen band_pen(band_colour);
  band_pen.setWidth(9);
  band_pen.setCapStyle(Qt::FlatCap);
  size_bars(band_series_, fitted_.size(), band_pen);
  size_bars(fitted_bar_series_, fitted_.size(), QPen(fitted_series_->color()));
  size_bars(bar_series_, predicted_.size(), QPen(predicted_series_->color()));
  std::size_t k = 0;
  for (const auto& [step, pr] : predicted_)
    bar_series_[k++]->replace(bar_points(pr.x, pr.T - pr.err, pr.T + pr.err, cap));
  k = 0;
  for (const auto& [step, ft] : fitted_) {
    fitted_bar_series_[k]->replace(bar_points(ft.x, ft.T - ft.err, ft.T + ft.err, cap));
    band_series_[k]->replace(bar_points(ft.x, ft.lo, ft.hi, 0.0));
    ++k;
  }
}

std::vector<QPointF> ComparisonChart::measured_points() const {
  return points_of(measured_series_);
}

std::vector<QPointF> ComparisonChart::predicted_points() const {
  return points_of(predicted_series_);
}

std::vector<QPointF> ComparisonChart::fitted_points() const {
  return points_of(fitted_series_);
}

std::vector<ComparisonChart::ErrorBar> ComparisonChart::error_bars() const {
  return bars_of(bar_series_);
}

std::vector<ComparisonChart::ErrorBar> ComparisonChart::fitted_error_bars() const {
  return bars_of(fitted_bar_series_);
}

std::vector<ComparisonChart::ErrorBar> ComparisonChart::model_bands() const {
  return bars_of(band_series_);
}

}  // namespace tocd::gui

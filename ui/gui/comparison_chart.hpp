#pragma once

#include <map>
#include <vector>

#include "error_bar_chart.hpp"

class QLineSeries;
class QPen;
class QScatterSeries;

namespace tocd::gui {

/// Transmission vs nominal strain: measured points, and simulated points with +/- one
/// standard error bars that fill in as predictions arrive. Keyed by step index, so a step
/// re-sent (a resumed run, a reloaded table) replaces its point instead of doubling it.
/// Optionally the same steps predicted with the sample's fitted law, with two bands: its
/// Monte Carlo error (a bar) and the model band over the fit's confidence laws (a wide,
/// pale bar behind it).
class ComparisonChart : public ErrorBarChart {
  Q_OBJECT

 public:
  explicit ComparisonChart(QWidget* parent = nullptr);

  void set_measured(int step, double nominal_strain, double T);
  void set_predicted(int step, double nominal_strain, double T, double T_stderr);
  /// The step predicted with the fitted law: T +- its Monte Carlo error, and [band_lo, band_hi].
  void set_fitted(int step, double nominal_strain, double T, double T_stderr, double band_lo, double band_hi);
  void clear_fitted();
  void clear();

  std::vector<QPointF> measured_points() const;
  std::vector<QPointF> predicted_points() const;
  std::vector<ErrorBar> error_bars() const;
  std::vector<QPointF> fitted_points() const;
  std::vector<ErrorBar> fitted_error_bars() const;
  std::vector<ErrorBar> model_bands() const;

 private:
  struct Predicted {
    double x, T, err;
  };
  struct Fitted {
    double x, T, err, lo, hi;
  };
  /// One line series per bar (Qt Charts cannot break a line): grows or shrinks `pool` to `n`.
  void size_bars(std::vector<QLineSeries*>& pool, std::size_t n, const QPen& pen);
  void rebuild();

  std::map<int, QPointF> measured_;
  std::map<int, Predicted> predicted_;
  std::map<int, Fitted> fitted_;
  QScatterSeries* measured_series_ = nullptr;
  QScatterSeries* predicted_series_ = nullptr;
  QScatterSeries* fitted_series_ = nullptr;
  std::vector<QLineSeries*> bar_series_, fitted_bar_series_, band_series_;
};

}  // namespace tocd::gui

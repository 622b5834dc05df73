#pragma once

#include <QChartView>
#include <QTimer>
#include <vector>

#include "decimator.hpp"

class QLineSeries;
class QValueAxis;

namespace tocd::gui {

/// A live chart of one stream (load vs displacement, power vs time, pressure vs time).
/// Samples are buffered as they come (cheap, any rate) and drawn at ~10 Hz through a
/// min/max decimator, so a 1 kHz stream costs a few hundred points per redraw.
class LiveChart : public QChartView {
  Q_OBJECT

 public:
  struct Options {
    QString title;
    QString x_label;
    QString y_label;
    double bucket_width = 0.02;      ///< decimation bucket along the key (s)
    double x_window = 0.0;           ///< > 0: show only the last x_window of x (time charts)
    std::size_t max_buckets = 2000;  ///< oldest buckets beyond this are forgotten
    int refresh_ms = 100;
  };

  explicit LiveChart(Options options, QWidget* parent = nullptr);

  /// Buffers one sample; `key` is the monotonic time (s) that orders decimation buckets.
  void add(double key, double x, double y);

  /// Draws what is buffered now (the timer calls this; tests call it directly).
  void refresh();

  void clear();

  /// The points currently drawn.
  std::vector<QPointF> displayed_points() const;
  std::size_t samples_seen() const noexcept { return decimator_.samples_seen(); }
  QLineSeries* series() const noexcept { return series_; }
  QValueAxis* x_axis() const noexcept { return x_axis_; }
  QValueAxis* y_axis() const noexcept { return y_axis_; }

 private:
  struct Pending {
    double key, x, y;
  };

  Options options_;
  MinMaxDecimator decimator_;
  std::vector<Pending> pending_;
  QLineSeries* series_ = nullptr;
  QValueAxis* x_axis_ = nullptr;
  QValueAxis* y_axis_ = nullptr;
  QTimer timer_;
  bool dirty_ = false;
};

}  // namespace tocd::gui

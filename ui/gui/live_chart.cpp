#include "live_chart.hpp"

#include <QChart>
#include <QLineSeries>
#include <QList>
#include <QValueAxis>

#include "chart_axes.hpp"

namespace tocd::gui {

LiveChart::LiveChart(Options options, QWidget* parent)
    : QChartView(parent),
      options_(std::move(options)),
      decimator_(options_.bucket_width, options_.max_buckets) {
  auto* chart = new QChart();
  chart->setTitle(options_.title);
  chart->legend()->hide();
  series_ = new QLineSeries(chart);
  // OpenGL would be faster still but does not exist on the offscreen platform; a few
  // thousand decimated points draw fine in software.
  chart->addSeries(series_);
  x_axis_ = new QValueAxis(chart);
  y_axis_ = new QValueAxis(chart);
  x_axis_->setTitleText(options_.x_label);
  y_axis_->setTitleText(options_.y_label);
  x_axis_->setRange(0, 1);
  y_axis_->setRange(0, 1);
  chart->addAxis(x_axis_, Qt::AlignBottom);
  chart->addAxis(y_axis_, Qt::AlignLeft);
  series_->attachAxis(x_axis_);
  series_->attachAxis(y_axis_);
  setChart(chart);
  setRenderHint(QPainter::Antialiasing, false);
  setMinimumSize(240, 180);

  connect(&timer_, &QTimer::timeout, this, &LiveChart::refresh);
  timer_.start(options_.refresh_ms);
}

void LiveChart::add(double key, double x, double y) {
  pending_.push_back({key, x, y});
  dirty_ = true;
}

void LiveChart::refresh() {
  if (!dirty_) return;
  dirty_ = false;
  for (const Pending& p : pending_) decimator_.add(p.key, QPointF(p.x, p.y));
  pending_.clear();

  std::vector<QPointF> pts = decimator_.points();
  double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;
  if (options_.x_window > 0.0 && !pts.empty()) {
    // Time charts scroll: only the last x_window is drawn and scaled for.
    const double x_end = pts.back().x();
    const double x_start = x_end - options_.x_window;
    std::erase_if(pts, [x_start](const QPointF& p) { return p.x() < x_start; });
  }
  series_->replace(QList<QPointF>(pts.begin(), pts.end()));
  if (bounds(pts, x_lo, x_hi, y_lo, y_hi)) {
    if (options_.x_window > 0.0) {
      x_axis_->setRange(std::max(x_lo, x_hi - options_.x_window), std::max(x_hi, x_lo + 1e-9));
    } else {
      const auto [a, b] = padded_range(x_lo, x_hi, {0.0, 1.0}, 0.02);
      x_axis_->setRange(a, b);
    }
    const auto [c, d] = padded_range(y_lo, y_hi, {0.0, 1.0});
    y_axis_->setRange(c, d);
  }
}

void LiveChart::clear() {
  pending_.clear();
  decimator_.clear();
  series_->clear();
  dirty_ = false;
}

std::vector<QPointF> LiveChart::displayed_points() const {
  const QList<QPointF> pts = series_->points();
  return {pts.begin(), pts.end()};
}

}  // namespace tocd::gui

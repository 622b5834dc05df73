#include "error_bar_chart.hpp"

#include <QChart>
#include <QLegendMarker>
#include <QLineSeries>
#include <QPen>
#include <QValueAxis>

namespace tocd::gui {

ErrorBarChart::ErrorBarChart(const QString& x_title, const QString& y_title, QWidget* parent)
    : QChartView(parent) {
  auto* chart = new QChart();
  x_axis_ = new QValueAxis(chart);
  y_axis_ = new QValueAxis(chart);
  x_axis_->setTitleText(x_title);
  y_axis_->setTitleText(y_title);
  chart->addAxis(x_axis_, Qt::AlignBottom);
  chart->addAxis(y_axis_, Qt::AlignLeft);
  setChart(chart);
  setRenderHint(QPainter::Antialiasing);
  setMinimumSize(300, 220);
}

void ErrorBarChart::add_series(QXYSeries* series) {
  chart()->addSeries(series);
  series->attachAxis(x_axis_);
  series->attachAxis(y_axis_);
}

QLineSeries* ErrorBarChart::add_bar(const QPen& pen) {
  auto* bar = new QLineSeries(chart());
  bar->setPen(pen);
  add_series(bar);
  for (QLegendMarker* marker : chart()->legend()->markers(bar)) marker->setVisible(false);
  return bar;
}

void ErrorBarChart::remove_bar(QLineSeries* bar) {
  chart()->removeSeries(bar);
  delete bar;
}

QList<QPointF> ErrorBarChart::bar_points(double x, double lo, double hi, double cap) {
  return {{x - cap, lo}, {x + cap, lo}, {x, lo}, {x, hi}, {x - cap, hi}, {x + cap, hi}};
}

std::vector<ErrorBarChart::ErrorBar> ErrorBarChart::bars_of(const std::vector<QLineSeries*>& bars) {
  std::vector<ErrorBar> out;
  for (const QLineSeries* s : bars) {
    const auto pts = s->points();
    out.push_back({pts[2].x(), pts[2].y(), pts[3].y()});
  }
  return out;
}

std::vector<QPointF> ErrorBarChart::points_of(const QXYSeries* series) {
  const auto pts = series->points();
  return {pts.begin(), pts.end()};
}

}  // namespace tocd::gui

#pragma once

#include <QImage>
#include <QWidget>
#include <array>
#include <utility>

#include "scalar_grid.hpp"

namespace tocd::gui {

/// Two fluence slices (e.g. pin-tip height and pin axis, or the same slice of two
/// simulations) drawn side by side on one logarithmic colour scale with one colour bar, so
/// equal colours mean equal fluence in both panels.
class FluenceMapPair : public QWidget {
  Q_OBJECT

 public:
  explicit FluenceMapPair(QWidget* parent = nullptr);

  void set_maps(ScalarGrid left, ScalarGrid right);
  void clear();

  /// The shared colour range as log10(value): the largest positive value of either map
  /// down to `dynamic_range_decades` below it (or the smallest positive value, if higher).
  /// {0, 0} when neither map has a positive value.
  std::pair<double, double> log10_range() const noexcept { return range_; }
  void set_dynamic_range_decades(double decades);

  /// The rendered panel (0 left, 1 right), one pixel per cell, row 0 at the bottom.
  const QImage& panel_image(int which) const { return images_.at(static_cast<std::size_t>(which)); }
  const ScalarGrid& grid(int which) const { return grids_.at(static_cast<std::size_t>(which)); }

  /// The colour of `value` on the current scale; values <= 0 or non-finite get the
  /// "no fluence" colour.
  QColor colour_of(double value) const;

  /// Perceptually ordered colour ramp (dark blue - green - yellow), t in [0, 1].
  static QColor ramp(double t);
  static QColor no_data_colour() { return QColor(40, 40, 40); }

  QSize sizeHint() const override { return {760, 340}; }

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  void update_range();
  QImage render(const ScalarGrid& g) const;

  std::array<ScalarGrid, 2> grids_;
  std::array<QImage, 2> images_;
  std::pair<double, double> range_{0.0, 0.0};
  double decades_ = 6.0;
};

}  // namespace tocd::gui

#pragma once

#include <initializer_list>

class QWidget;

namespace tocd::gui {

/// A borderless widget of `parent` holding `rows` in a grid, row by row, as the views lay out
/// their charts (so the grid lines up with the views' own margins).
QWidget* widget_grid(QWidget* parent, std::initializer_list<std::initializer_list<QWidget*>> rows);

}  // namespace tocd::gui

#include "widget_grid.hpp"

#include <QGridLayout>
#include <QWidget>

namespace tocd::gui {

QWidget* widget_grid(QWidget* parent, std::initializer_list<std::initializer_list<QWidget*>> rows) {
  auto* holder = new QWidget(parent);
  auto* grid = new QGridLayout(holder);
  grid->setContentsMargins(0, 0, 0, 0);
  int r = 0;
  for (const auto& row : rows) {
    int c = 0;
    for (QWidget* w : row) grid->addWidget(w, r, c++);
    ++r;
  }
  return holder;
}

}  // namespace tocd::gui

#pragma once

#include <QMainWindow>

namespace tocd::gui {

/// The workbench's main window: instruments, run control, charts, step table.
class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(QWidget* parent = nullptr);
};

}  // namespace tocd::gui

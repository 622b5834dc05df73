#include "main_window.hpp"

#include <QLabel>
#include <QStatusBar>

#include "tocd/core/version.hpp"

namespace tocd::gui {

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  setWindowTitle(QStringLiteral("tocdlab %1").arg(QString::fromUtf8(tocd::version().data())));
  resize(1280, 800);
  statusBar()->showMessage(tr("No lab connected"));
}

}  // namespace tocd::gui

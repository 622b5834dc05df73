#include <QApplication>

#include "main_window.hpp"

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  QApplication::setApplicationName(QStringLiteral("tocdlab"));
  QApplication::setOrganizationName(QStringLiteral("tocdlab"));
  tocd::gui::MainWindow window;
  window.show();
  return QApplication::exec();
}

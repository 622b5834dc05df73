#pragma once

#include <QObject>
#include <QString>

#include "tocd/acquisition/engine.hpp"

namespace tocd::gui {

class MainWindow;

/// The one demo protocol (protocols/demo.toml, the text `tocdlab demo` runs), as TOML.
QString demo_protocol_toml();

/// `tocdlab-gui --demo`: starts the simulated lab, loads the demo protocol, starts the run
/// through the window's own actions, waits for the run and every prediction, optionally
/// saves a screenshot of the window, then quits. Exit code 0 when every step has a measured
/// and a predicted transmission (or measured only, when the build has no simulator).
class DemoDriver : public QObject {
  Q_OBJECT

 public:
  DemoDriver(MainWindow& window, QString screenshot_path, QObject* parent = nullptr);
  void start();

 signals:
  void done(int exit_code);

 private:
  void on_lab_ready();
  void on_finished(acquisition::EngineState state);
  void take_screenshot_and_quit(int exit_code);

  MainWindow& window_;
  QString screenshot_;
  bool started_ = false;
  bool paused_ = false;  ///< the run paused on a fault: the demo has failed
};

}  // namespace tocd::gui

#pragma once

#include <QSettings>
#include <QString>
#include <QStringList>
#include <memory>

class QMainWindow;

namespace tocd::gui {

/// What the window remembers between sessions (QSettings: ~/.config/tocdlab/tocdlab.conf on
/// Linux): last files opened, the simulation photon budget, the simulated-lab clock factor,
/// window geometry. Every getter has a sensible default for a first start.
class GuiSettings {
 public:
  /// Uses the application's default QSettings.
  GuiSettings();
  /// Uses `settings` (tests give an INI file in a temporary folder).
  explicit GuiSettings(std::unique_ptr<QSettings> settings);

  QString last_lab_path() const;
  void set_last_lab_path(const QString& path);
  QString last_protocol_path() const;
  void set_last_protocol_path(const QString& path);
  QString last_database_path() const;
  void set_last_database_path(const QString& path);

  /// Most recent first, at most 8, no duplicates.
  QStringList recent_databases() const;
  void add_recent_database(const QString& path);

  qulonglong photons() const;  ///< simulation photon budget
  void set_photons(qulonglong photons);
  double clock_factor() const;  ///< simulated lab: simulated seconds per real second
  void set_clock_factor(double factor);

  void save_window(const QMainWindow& window);
  void restore_window(QMainWindow& window) const;

  void sync();
  QSettings& raw() { return *settings_; }

 private:
  std::unique_ptr<QSettings> settings_;
};

}  // namespace tocd::gui

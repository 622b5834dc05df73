#include "gui_settings.hpp"

#include <QMainWindow>
#include <algorithm>

namespace tocd::gui {

namespace {
constexpr int kMaxRecent = 8;
constexpr qulonglong kDefaultPhotons = 100000;
constexpr double kDefaultClockFactor = 10.0;
}  // namespace

GuiSettings::GuiSettings() : settings_(std::make_unique<QSettings>()) {}

GuiSettings::GuiSettings(std::unique_ptr<QSettings> settings) : settings_(std::move(settings)) {}

QString GuiSettings::last_lab_path() const {
  return settings_->value("files/lab").toString();
}
void GuiSettings::set_last_lab_path(const QString& path) {
  settings_->setValue("files/lab", path);
}
QString GuiSettings::last_protocol_path() const {
  return settings_->value("files/protocol").toString();
}
void GuiSettings::set_last_protocol_path(const QString& path) {
  settings_->setValue("files/protocol", path);
}
QString GuiSettings::last_database_path() const {
  return settings_->value("files/database").toString();
}
void GuiSettings::set_last_database_path(const QString& path) {
  settings_->setValue("files/database", path);
}

QStringList GuiSettings::recent_databases() const {
  return settings_->value("files/recent_databases").toStringList();
}

void GuiSettings::add_recent_database(const QString& path) {
  QStringList list = recent_databases();
  list.removeAll(path);
  list.prepend(path);
  while (list.size() > kMaxRecent) list.removeLast();
  settings_->setValue("files/recent_databases", list);
}

qulonglong GuiSettings::photons() const {
  bool ok = false;
  const qulonglong n = settings_->value("simulation/photons", kDefaultPhotons).toULongLong(&ok);
  return ok && n > 0 ? n : kDefaultPhotons;
}
void GuiSettings::set_photons(qulonglong photons) {
  settings_->setValue("simulation/photons", photons);
}

double GuiSettings::clock_factor() const {
  bool ok = false;
  const double f = settings_->value("lab/clock_factor", kDefaultClockFactor).toDouble(&ok);
  return ok && f > 0.0 ? f : kDefaultClockFactor;
}
void GuiSettings::set_clock_factor(double factor) {
  settings_->setValue("lab/clock_factor", factor);
}

void GuiSettings::save_window(const QMainWindow& window) {
  settings_->setValue("window/geometry", window.saveGeometry());
  settings_->setValue("window/state", window.saveState());
}

void GuiSettings::restore_window(QMainWindow& window) const {
  const QByteArray geometry = settings_->value("window/geometry").toByteArray();
  if (!geometry.isEmpty()) window.restoreGeometry(geometry);
  const QByteArray state = settings_->value("window/state").toByteArray();
  if (!state.isEmpty()) window.restoreState(state);
}

void GuiSettings::sync() {
  settings_->sync();
}

}  // namespace tocd::gui

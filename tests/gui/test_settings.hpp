#pragma once

// The window tests' settings: a file of the test's own, so that no test reads what the user
// (or another test) left in the real settings, nor changes them.

#include <QSettings>
#include <QString>
#include <QTemporaryDir>
#include <memory>

#include "gui_settings.hpp"

namespace tocd::gui::testing {

/// Settings kept in `dir`/gui.ini, gone with the directory.
inline std::unique_ptr<GuiSettings> settings_in(const QTemporaryDir& dir) {
  return std::make_unique<GuiSettings>(
      std::make_unique<QSettings>(dir.filePath(QStringLiteral("gui.ini")), QSettings::IniFormat));
}

}  // namespace tocd::gui::testing

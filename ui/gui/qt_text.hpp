#pragma once
// Text from tocdlab's libraries (std::string, UTF-8) as Qt's text.

#include <QString>
#include <string>

namespace tocd::gui {

inline QString qs(const std::string& s) {
  return QString::fromStdString(s);
}

}  // namespace tocd::gui

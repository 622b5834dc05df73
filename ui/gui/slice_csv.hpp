#pragma once

#include <QString>
#include <stdexcept>

#include "scalar_grid.hpp"

namespace tocd::gui {

/// A fluence slice file that cannot be shown; the message names the file and line.
class SliceCsvError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads a fluence slice CSV as written by the study (`x_mm,y_mm,z_mm,region,fluence,
/// fluence_se`, one line per grid point, empty fluence outside the mesh) into a grid. The two
/// coordinates that vary become the picture's axes (x-y for the slice at pin-tip height, x-z
/// for the slice through the pin axis); points outside the mesh become NaN (no data).
ScalarGrid read_slice_csv(const QString& path);

/// The same from CSV text; `source_name` prefixes error messages.
ScalarGrid parse_slice_csv(const QString& text, const QString& source_name);

}  // namespace tocd::gui

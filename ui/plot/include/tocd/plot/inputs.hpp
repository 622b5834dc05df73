#pragma once

#include <filesystem>
#include <string>

#include "tocd/plot/figures.hpp"

namespace tocd::plot {

/// Reads a fluence slice CSV as the study writes it (`x_mm,y_mm,z_mm,region,fluence,
/// fluence_se`, one line per grid point, empty fluence outside the mesh). The two coordinates
/// that vary become the axes (x-y for the horizontal slice, x-z for the vertical one).
/// Throws tocd::ConfigError naming the file and line.
Slice read_slice_csv(const std::filesystem::path& path);
Slice parse_slice_csv(const std::string& text, const std::string& source_name);

/// The bars of a study's JSON (`tocdlab study ... --json FILE`): one bar per simulation,
/// the value of `column` (T, T_rel_a, T_rel_b, side_loss, ...) with its `<column>_se` (or
/// `<column>_stderr`) as error bar. Simulations without that value are left out.
/// Throws tocd::ConfigError naming the file and what is missing.
BarFigure read_study_bars(const std::filesystem::path& json_path, const std::string& column);
BarFigure parse_study_bars(const std::string& json_text, const std::string& column,
                           const std::string& source_name);

/// The tornado of `tocdlab study sensitivity --json` (its `tornado` array: factor, label, dT,
/// dT_se, sorted by |dT|). Throws tocd::ConfigError naming the file and what is missing.
TornadoFigure read_sensitivity_tornado(const std::filesystem::path& json_path);
TornadoFigure parse_sensitivity_tornado(const std::string& json_text, const std::string& source_name);

}  // namespace tocd::plot

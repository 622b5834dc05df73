#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tocd/plot/figures.hpp"

namespace tocd::plot {

/// Reads a fluence slice CSV as the study writes it (`x_mm,y_mm,z_mm,region,fluence,
/// fluence_se`, one line per grid point, empty fluence outside the mesh). The two coordinates
/// that vary become the axes (x-y for the horizontal slice, x-z for the vertical one).
/// Throws tocd::ConfigError naming the file and line.
Slice read_slice_csv(const std::filesystem::path& path);
Slice parse_slice_csv(const std::string& text, const std::string& source_name);

/// The title of a slice figure: the state the slices show, from the JSON of the run that wrote
/// them, a study's (`study ... -o FILE.json` or `--json`: the simulation whose fluence CSVs have
/// the slices' file names) or a prediction's (`predict --json`). It states the displacement,
/// the skin thickness and the nominal strain (displacement / thickness) of that state, e.g.
/// "fluence of sim 3 (native): 1.5 mm into 2.5 mm skin, 60 % strain". Throws
/// tocd::ConfigError naming the file when it is not such a JSON or none of its states wrote
/// these slices.
std::string slice_state_title(const std::string& json_text, const std::vector<std::string>& slice_files,
                              const std::string& source_name);
std::string read_slice_state_title(const std::filesystem::path& json_path,
                                   const std::vector<std::string>& slice_files);

/// The bars of a study's JSON (`tocdlab study ... --json FILE`): one bar per simulation,
/// the value of `column` (T, T_rel_a, T_rel_b, side_loss, ...) with its `<column>_se` (or
/// `<column>_stderr`) as error bar, labelled by the study's own description of the simulation
/// (its optics, displacement and nominal strain; glass only for the baseline). Simulations
/// without that value are left out, and so, for a relative column (T_rel_a, T_rel_b), are the
/// simulations before its reference, as the study's table leaves them ("-").
/// Throws tocd::ConfigError naming the file and what is missing.
BarFigure read_study_bars(const std::filesystem::path& json_path, const std::string& column);
BarFigure parse_study_bars(const std::string& json_text, const std::string& column,
                           const std::string& source_name);

/// The tornado of `tocdlab study sensitivity --json` (its `tornado` array: factor, label, dT,
/// dT_se, sorted by |dT|). Throws tocd::ConfigError naming the file and what is missing.
TornadoFigure read_sensitivity_tornado(const std::filesystem::path& json_path);
TornadoFigure parse_sensitivity_tornado(const std::string& json_text, const std::string& source_name);

}  // namespace tocd::plot

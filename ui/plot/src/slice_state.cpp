#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "input_file.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/inputs.hpp"

namespace tocd::plot {
namespace {

// An object whose "fluence" block names one of the slice files (by file name: the JSON keeps
// the paths as the run was given them, the plot may be run from elsewhere). A study keeps one
// per simulation, a prediction one at its top or under "step".
const nlohmann::json* writer_of(const nlohmann::json& j, const std::vector<std::string>& files) {
  if (j.is_object()) {
    const auto f = j.find("fluence");
    if (f != j.end() && f->is_object())
      for (const char* key : {"horizontal_csv", "vertical_csv"})
        if (f->contains(key) && (*f)[key].is_string())
          for (const auto& file : files)
            if (std::filesystem::path((*f)[key].get<std::string>()).filename() ==
                std::filesystem::path(file).filename())
              return &j;
    for (const auto& [key, value] : j.items())
      if (const auto* found = writer_of(value, files)) return found;
  } else if (j.is_array()) {
    for (const auto& value : j)
      if (const auto* found = writer_of(value, files)) return found;
  }
  return nullptr;
}

}  // namespace

std::string slice_state_title(const std::string& json_text, const std::vector<std::string>& slice_files,
                              const std::string& source) {
  nlohmann::json j = detail::parse_input_json(json_text, source);
  const nlohmann::json* w = writer_of(j, slice_files);
  if (w == nullptr || !w->contains("config") || !(*w)["config"].is_object())
    throw ConfigError(source +
                      ": no simulation in it wrote these slices (give the JSON of the study or prediction "
                      "whose --fluence-dir holds them: study ... -o FILE.json, predict ... --json)");
  const auto& c = (*w)["config"];
  std::string who = "fluence";
  if (w->contains("sim") && (*w)["sim"].is_number_integer())
    who = fmt::format("fluence of sim {}", (*w)["sim"].get<int>());
  if (c.value("baseline", false)) return who + ": glass only (pin tip on the slide, no skin)";
  // The compressed region's optics as the study names them; a prediction names its material.
  std::string optics = w->value("optics", std::string());
  if (optics.empty())
    optics = c.value("optics_model", std::string()) == "threshold" && c.contains("compressed_optics")
                 ? c["compressed_optics"].value("name", std::string())
                 : c.value("optics_model", std::string());
  const double d = c.value("displacement_mm", NAN), h = c.value("thickness_mm", NAN);
  if (!std::isfinite(d) || !std::isfinite(h) || !(h > 0))
    throw ConfigError(source + ": the state that wrote these slices has no displacement_mm and thickness_mm");
  return fmt::format("{}{}: {:g} mm into {:g} mm skin, {:.0f} % strain", who,
                     optics.empty() ? std::string() : " (" + optics + ")", d, h, 100.0 * d / h);
}

std::string read_slice_state_title(const std::filesystem::path& json_path,
                                   const std::vector<std::string>& slice_files) {
  return slice_state_title(detail::read_input_file(json_path, "the slices' state JSON"), slice_files,
                           json_path.string());
}

}  // namespace tocd::plot

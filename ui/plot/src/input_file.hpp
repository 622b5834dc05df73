#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "tocd/core/error.hpp"
#include "tocd/core/text_file.hpp"

namespace tocd::plot::detail {

/// The whole text of an input file of a figure; ConfigError "cannot read <what> '<path>'"
/// when it cannot be opened or is a directory.
inline std::string read_input_file(const std::filesystem::path& path, std::string_view what) {
  auto text = read_text_file(path);
  if (!text) throw ConfigError("cannot read " + std::string(what) + " '" + path.string() + "'");
  return std::move(*text);
}

/// `json_text` parsed; ConfigError "<source>: not valid JSON (...)" when it is not.
inline nlohmann::json parse_input_json(const std::string& json_text, const std::string& source) {
  try {
    return nlohmann::json::parse(json_text);
  } catch (const nlohmann::json::parse_error& e) {
    throw ConfigError(source + ": not valid JSON (" + e.what() + ")");
  }
}

}  // namespace tocd::plot::detail

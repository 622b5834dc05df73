#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

#include "tocd/core/error.hpp"

namespace tocd::plot::detail {

/// The whole text of an input file of a figure; ConfigError "cannot read <what> '<path>'"
/// when it cannot be opened or is a directory.
inline std::string read_input_file(const std::filesystem::path& path, std::string_view what) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path))
    throw ConfigError("cannot read " + std::string(what) + " '" + path.string() + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace tocd::plot::detail

#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace tocd {

/// The whole content of the file at `path` (bytes as stored), or nullopt when it cannot be
/// opened or is a directory (which a stream "opens" and then reads as empty). Each caller
/// raises its own error, naming what the file was for.
std::optional<std::string> read_text_file(const std::filesystem::path& path);

}  // namespace tocd

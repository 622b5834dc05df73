// Shared by the fuzz targets: quiet logging and a scratch folder for targets whose entry point
// reads files. Each target is its own process, so a folder per process keeps parallel runs
// (ctest -j) apart.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include <unistd.h>

#include "tocd/core/log.hpp"
#include "tocd/test/temp_dir.hpp"

namespace tocd::fuzz {

/// Warnings about hostile input are expected by the thousand; printing them would only slow
/// the fuzzer down.
inline void quiet_logging() {
  tocd::set_log_level("off");
}

/// A folder of this process under the system's temporary folder, removed at exit.
inline const std::filesystem::path& scratch_dir() {
  static const tocd::test::TempDir dir("fuzz");
  return dir.path();
}

inline void write_file(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace tocd::fuzz

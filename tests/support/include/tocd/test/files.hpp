#pragma once

// Reading and writing a test's files whole.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace tocd::test {

/// The bytes of `p`; empty when it cannot be read (the test's assertion says what was missing).
inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Writes `text` to `p`, replacing it; returns whether every byte was written.
inline bool write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
  return static_cast<bool>(out.flush());
}

}  // namespace tocd::test

#pragma once

// Reading and writing a test's files whole.

#include <cstdint>
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

/// Writes 2,000 pseudo-random bytes (a linear congruential sequence from `seed`) 100 bytes into
/// the 4 KiB page at the middle of `p`: a database's b-tree is damaged, its header is not.
inline void scribble_over_middle_page(const std::filesystem::path& p, std::uint32_t seed) {
  std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(std::filesystem::file_size(p) / 2 / 4096 * 4096 + 100));
  std::uint32_t x = seed;
  for (int i = 0; i < 2000; ++i) {
    x = x * 1664525u + 1013904223u;
    f.put(static_cast<char>(x >> 24));
  }
}

}  // namespace tocd::test

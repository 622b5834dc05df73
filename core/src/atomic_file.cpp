#include "tocd/core/atomic_file.hpp"

#include <fmt/format.h>

#include "tocd/core/error.hpp"

namespace tocd {

AtomicFile::AtomicFile(std::filesystem::path path)
    : path_(std::move(path)),
      part_(path_.string() + ".part"),
      out_(part_, std::ios::binary | std::ios::trunc) {
  if (!out_) throw tocd::Error(fmt::format("cannot write {}", part_.string()));
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  out_.close();
  std::error_code ignored;
  std::filesystem::remove(part_, ignored);
}

void AtomicFile::commit() {
  out_.flush();
  if (!out_) throw tocd::Error(fmt::format("cannot write {} (disk full?)", part_.string()));
  out_.close();
  std::error_code ec;
  std::filesystem::rename(part_, path_, ec);
  if (ec)
    throw tocd::Error(
        fmt::format("cannot rename {} to {}: {}", part_.string(), path_.string(), ec.message()));
  committed_ = true;
}

void write_file_atomically(const std::filesystem::path& path, const std::string& text) {
  AtomicFile file(path);
  file.stream() << text;
  file.commit();
}

}  // namespace tocd

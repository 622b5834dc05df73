#include "tocd/core/atomic_file.hpp"

#include <fmt/format.h>

#include "tocd/core/error.hpp"

namespace tocd {

namespace {

/// Where the text goes until commit(): NAME.part, or NAME itself when it is a device or a FIFO.
std::filesystem::path part_path(const std::filesystem::path& path) {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st) &&
      !std::filesystem::is_directory(st))
    return path;
  return path.string() + ".part";
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path path)
    : path_(std::move(path)), part_(part_path(path_)), out_(part_, std::ios::binary | std::ios::trunc) {
  if (!out_) throw tocd::Error(fmt::format("cannot write {}", part_.string()));
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  out_.close();
  if (part_ == path_) return;
  std::error_code ignored;
  std::filesystem::remove(part_, ignored);
}

void AtomicFile::commit() {
  out_.flush();
  if (out_) out_.close();  // close() flushes what the stream still holds and can fail too
  if (!out_) throw tocd::Error(fmt::format("cannot write {} (disk full?)", part_.string()));
  if (part_ != path_) {
    std::error_code ec;
    std::filesystem::rename(part_, path_, ec);
    if (ec)
      throw tocd::Error(
          fmt::format("cannot rename {} to {}: {}", part_.string(), path_.string(), ec.message()));
  }
  committed_ = true;
}

void write_file_atomically(const std::filesystem::path& path, const std::string& text) {
  AtomicFile file(path);
  file.stream() << text;
  file.commit();
}

}  // namespace tocd

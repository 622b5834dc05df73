#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace tocd {

/// An output file that appears under its name only when it is complete: the text goes to
/// NAME.part, and commit() flushes it and renames it over NAME. A file left behind by a
/// crash, a kill or an error is the .part file, never a NAME that looks finished; destroyed
/// without commit(), the part file is removed. Throws tocd::Error naming the file when it
/// cannot be opened, written or renamed ("disk full?" when a write or the flush failed).
///
/// A NAME that exists and is no regular file (a device such as /dev/stdout or /dev/null, a
/// FIFO) is written directly: it cannot be replaced by a rename, and it is no file a reader
/// could mistake for finished. commit() still checks that every byte was taken.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return out_; }
  void commit();

 private:
  std::filesystem::path path_, part_;  ///< part_ == path_ when written directly
  std::ofstream out_;
  bool committed_ = false;
};

/// Writes `text` to `path` through an AtomicFile.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace tocd

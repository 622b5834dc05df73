#pragma once

// A fresh directory for one test (or one fixture), removed with everything in it when the
// object goes. Names carry the process id and a counter so that tests running side by side
// under `ctest -j` never share one.

#include <atomic>
#include <filesystem>
#include <string>
#include <system_error>

#include <unistd.h>

namespace tocd::test {

class TempDir {
 public:
  /// A directory named tocd_<purpose>_<pid>_<n> under the system's temporary directory.
  explicit TempDir(const std::string& purpose = "test") {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("tocd_" + purpose + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;  // a test's failure must not become a crash in its clean-up
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  const std::filesystem::path& path() const { return path_; }
  operator const std::filesystem::path&() const { return path_; }  // NOLINT: a path is what it is

 private:
  std::filesystem::path path_;
};

/// `name` in a directory of this test process's own, made on first use and removed when the
/// process exits: for files that outlive one test's scope.
inline std::filesystem::path process_temp_path(const std::string& name) {
  static const TempDir dir("process");
  return dir / name;
}

}  // namespace tocd::test

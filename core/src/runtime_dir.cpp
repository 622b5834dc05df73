#include "tocd/core/runtime_dir.hpp"

#include <cerrno>
#include <cstdlib>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

namespace tocd {

namespace {

// What the XDG base directory specification asks of the runtime directory: ours, 0700.
bool usable(const char* path) {
  struct stat st {};
  return path && *path && ::lstat(path, &st) == 0 && S_ISDIR(st.st_mode) && st.st_uid == ::getuid() &&
         (st.st_mode & 0777) == 0700;
}

}  // namespace

void ensure_runtime_dir() noexcept {
  if (usable(std::getenv("XDG_RUNTIME_DIR"))) return;
  try {
    const std::string dir = "/tmp/tocdlab-runtime-" + std::to_string(::getuid());
    if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST) return;
    // Someone else's directory under that name, or one with other modes, is not used.
    if (!usable(dir.c_str())) return;
    ::setenv("XDG_RUNTIME_DIR", dir.c_str(), 1);
  } catch (...) {
    // Out of memory building a path: Qt's own fallback and its warning remain.
  }
}

}  // namespace tocd

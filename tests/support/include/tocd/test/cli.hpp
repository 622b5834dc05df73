#pragma once

// Runs the tocdlab executable (or any shell command) as a user does, with stdout and stderr
// captured apart.

#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <sys/wait.h>

#include "tocd/test/files.hpp"

namespace tocd::test {

struct CliResult {
  int status = -1;  ///< exit status; -1 when killed by a signal
  std::string out, err;
};

/// `command` through the shell in `dir`, stdin from /dev/null; stdout and stderr go through
/// dir/stdout.txt and dir/stderr.txt. The command runs as a group, so a redirection or a
/// ulimit inside it applies to it alone and wins over these.
inline CliResult run_shell(const std::string& command, const std::filesystem::path& dir) {
  const auto out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd = fmt::format("cd '{}' && {{ {}; }} < /dev/null > '{}' 2> '{}'", dir.string(),
                                      command, out.string(), err.string());
  const int rc = std::system(cmd.c_str());
  CliResult r;
  r.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  return r;
}

/// `prefix exe args` through the shell in `dir` (args are shell words; `prefix` may set
/// variables or run commands first, such as a ulimit), as run_shell().
inline CliResult run_cli(const std::string& exe, const std::string& args, const std::filesystem::path& dir,
                         const std::string& prefix = "") {
  return run_shell(fmt::format("{} '{}' {}", prefix, exe, args), dir);
}

}  // namespace tocd::test

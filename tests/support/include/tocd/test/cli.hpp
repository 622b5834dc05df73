#pragma once

// Runs the tocdlab executable as a user does, with stdout and stderr captured apart.

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

/// `env exe args` through the shell in `dir` (args are shell words), stdin from /dev/null;
/// stdout and stderr go through dir/stdout.txt and dir/stderr.txt.
inline CliResult run_cli(const std::string& exe, const std::string& args, const std::filesystem::path& dir,
                         const std::string& env = "") {
  const auto out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd = fmt::format("cd '{}' && {} '{}' {} < /dev/null > '{}' 2> '{}'", dir.string(), env,
                                      exe, args, out.string(), err.string());
  const int rc = std::system(cmd.c_str());
  CliResult r;
  r.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  return r;
}

}  // namespace tocd::test

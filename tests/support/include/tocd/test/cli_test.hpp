#pragma once

// A test that runs the tocdlab executable, as a user does, in a directory of its own.
// The test's target defines TOCDLAB_EXE (the executable's path).

#include <string>

#include <gtest/gtest.h>

#include "tocd/test/cli.hpp"
#include "tocd/test/temp_dir.hpp"

#ifndef TOCDLAB_EXE
#error "tocd/test/cli_test.hpp runs tocdlab: the test's target defines TOCDLAB_EXE"
#endif

namespace tocd::test {

class CliTest : public ::testing::Test {
 protected:
  /// Runs `tocdlab args` in dir_ (after `prefix`, shell commands such as a ulimit); out_ and
  /// err_ hold what it wrote. Returns its exit status (-1 when a signal ended it).
  int tocdlab(const std::string& args, const std::string& prefix = "") {
    const CliResult r = run_cli(TOCDLAB_EXE, args, dir_, prefix);
    out_ = r.out;
    err_ = r.err;
    return r.status;
  }

  /// Writes `text` to dir_/name and returns that path.
  std::filesystem::path write(const std::string& name, const std::string& text) {
    write_file(dir_ / name, text);
    return dir_ / name;
  }

  TempDir dir_{"cli"};
  std::string out_, err_;
};

}  // namespace tocd::test

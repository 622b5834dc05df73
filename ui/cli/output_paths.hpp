#pragma once

// Checks for options that name something the command will write, run when the command line
// is parsed: a path that cannot be written is a usage error before any work (a demo's sample
// preparation, a study's Monte Carlo), not an error after it.

#include <string>

#include <CLI/CLI.hpp>

namespace tocd::cli {

/// Why `path` cannot be created or overwritten as a file ("" when it can): it is a
/// directory (or ends in '/'), its directory does not exist or cannot be written.
std::string output_file_problem(const std::string& path);

/// Why `path` cannot be used as an output directory ("" when it can): it exists and is no
/// directory, or the nearest existing directory above it cannot be written.
std::string output_dir_problem(const std::string& path);

/// CLI11 checks over the two: "FILE" and "DIR" in the help.
CLI::Validator output_file();
CLI::Validator output_dir();

}  // namespace tocd::cli

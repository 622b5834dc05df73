#pragma once

// The check of every `--db`: a file path, or a PostgreSQL connection URI (docs/database.md).

#include <CLI/CLI.hpp>

namespace tocd::cli {

/// A database that will be written: a server URI, or a file that can be created or written
/// (output_file's check). "FILE|URI" in the help.
CLI::Validator database_output();

/// A database that is only read: a server URI, or an existing file.
CLI::Validator database_input();

}  // namespace tocd::cli

#pragma once

// The check of every `--db`: a file path, or a PostgreSQL connection URI (docs/database.md).

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

namespace tocd::cli {

/// A database that will be written: a server URI, or a file that can be created or written
/// (output_file's check). "FILE|URI" in the help.
CLI::Validator database_output();

/// A database that is only read: a server URI, or an existing file.
CLI::Validator database_input();

/// The required `--db` of a command that reads recorded runs: a file or a server URI, described
/// the same way in every command's help.
CLI::Option* add_runs_database(CLI::App* cmd, std::string& db);

/// The required `--run` that picks one recorded run: an id >= 1, as `tocdlab runs` lists them.
CLI::Option* add_run_id(CLI::App* cmd, std::int64_t& run);

}  // namespace tocd::cli

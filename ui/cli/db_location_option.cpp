#include "db_location_option.hpp"

#include <filesystem>
#include <limits>
#include <string>

#include "numeric_options.hpp"
#include "output_paths.hpp"
#include "tocd/db/location.hpp"

namespace tocd::cli {

CLI::Validator database_output() {
  return CLI::Validator(
      [](std::string& v) { return tocd::db::is_server_uri(v) ? std::string() : output_file_problem(v); },
      "FILE|URI");
}

CLI::Validator database_input() {
  return CLI::Validator(
      [](std::string& v) {
        if (tocd::db::is_server_uri(v)) return std::string();
        std::error_code ec;
        if (!std::filesystem::is_regular_file(v, ec)) return "File does not exist: " + v;
        return std::string();
      },
      "FILE|URI");
}

CLI::Option* add_runs_database(CLI::App* cmd, std::string& db) {
  return cmd->add_option("--db", db, "measurement database file, or a PostgreSQL server (postgresql://...)")
      ->required();
}

CLI::Option* add_run_id(CLI::App* cmd, std::int64_t& run) {
  return cmd->add_option("--run", run, "run id (see tocdlab runs)")
      ->check(whole_in(std::int64_t{1}, std::numeric_limits<std::int64_t>::max()))
      ->required();
}

}  // namespace tocd::cli

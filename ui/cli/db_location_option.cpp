#include "db_location_option.hpp"

#include <filesystem>
#include <string>

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

}  // namespace tocd::cli

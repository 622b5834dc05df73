#include "tocd/db/location.hpp"

#include <regex>

namespace tocd::db {

bool is_server_uri(std::string_view location) noexcept {
  return location.starts_with("postgresql://") || location.starts_with("postgres://");
}

std::string display_location(std::string_view location) {
  std::string out(location);
  if (!is_server_uri(location)) return out;
  // A password belongs in ~/.pgpass or PGPASSWORD; one given in the URI anyway must not reach
  // a log, a terminal's scrollback or a JSON summary.
  static const std::regex user_password(R"(^(postgres(?:ql)?://[^:@/?]*):[^@/?]*@)");
  static const std::regex query_password(R"(([?&]password=)[^&]*)");
  out = std::regex_replace(out, user_password, "$1:***@");
  return std::regex_replace(out, query_password, "$1***");
}

}  // namespace tocd::db

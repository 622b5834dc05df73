#pragma once

// Where a database is: an SQLite file path, or a PostgreSQL server named by a connection URI
// (docs/database.md, "PostgreSQL"). Every `--db` takes either; these say which, and how to
// name one in a message without its password.

#include <string>
#include <string_view>

namespace tocd::db {

/// True for a libpq connection URI ("postgresql://..." or "postgres://..."); anything else is
/// a file path.
bool is_server_uri(std::string_view location) noexcept;

/// The location as messages show it: a URI with its password (user:PASSWORD@ or
/// password=... in the query) replaced by "***"; a path unchanged.
std::string display_location(std::string_view location);

}  // namespace tocd::db

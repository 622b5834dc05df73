#pragma once

// Schema of a tocdlab database, its migrations, and the check that a file is one.

#include <filesystem>
#include <string>

#include "sqlite_util.hpp"

namespace tocd::db::detail {

/// What an existing file is, found without modifying it (read-only connection).
struct FileIdentity {
  bool is_new = false;  // absent, empty, or an SQLite file with no tables and no application id
  int schema_version = 0;
};

/// Throws DatabaseError when `path` exists but is not a tocdlab database, or comes from a
/// newer schema than this build knows. Never writes to the file.
FileIdentity identify(const std::filesystem::path& path);

/// Brings an open read-write connection to the current schema, in one transaction.
/// Returns the version found before migrating.
int migrate(const Connection& c);

/// Settings every read-write connection uses (WAL, synchronous=NORMAL, foreign keys). Returns
/// the journal mode in force ("wal" unless SQLite could not switch; then a warning is logged).
std::string configure_read_write(const Connection& c);

/// Opens a read-only connection to an existing tocdlab database of the current schema. When
/// given, `note` receives what open_existing_read_only says about an immutable open ("" else).
Connection open_read_only(const std::filesystem::path& path, std::string* note = nullptr);

}  // namespace tocd::db::detail

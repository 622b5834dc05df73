#pragma once

// The tocdlab schema on a PostgreSQL server: the same tables, columns and views as an SQLite
// file of schema Database::kSchemaVersion (docs/database.md), in PostgreSQL's types, plus the
// server's own record of pushed runs.

#include "pg_util.hpp"

namespace tocd::db::pg {

/// The lock key space of tocdlab's advisory locks on a server ("TOCD", as the SQLite
/// application id): (kLockSpace, 0) guards schema creation, (kLockSpace, run id) is a run's
/// recording lock, (kPushLockSpace, hash of a run's uuid) a push of that run.
inline constexpr int kLockSpace = 0x544F4344;
inline constexpr int kPushLockSpace = 0x544F4350;  // "TOCP"

/// Creates the schema in an empty database (the connection's current schema), upgrades
/// tocdlab's schema of an older version there to the current one, or checks that the one there
/// is current. Refuses (DatabaseError, nothing changed) a database holding other tables, a
/// tocdlab schema of a newer version, or one this build cannot upgrade (also when the
/// connection's role may not alter the tables). Concurrent callers create or upgrade it once.
void ensure_schema(const Connection& c);

/// Checks, without writing, that the database holds tocdlab's schema of the current version.
void require_schema(const Connection& c);

}  // namespace tocd::db::pg

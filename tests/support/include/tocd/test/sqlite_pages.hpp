#pragma once

// How much a SQLite database holds, read the way SQLite itself counts it (the including test
// links SQLite, as every database test does).

#include <cstdint>
#include <filesystem>

#include <sqlite3.h>

namespace tocd::test {

/// Pages the database at `path` holds now (its logical size, WAL included); 0 when unreadable.
inline std::uint64_t page_count(const std::filesystem::path& path) {
  sqlite3* c = nullptr;
  sqlite3_open_v2(path.c_str(), &c, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* st = nullptr;
  sqlite3_prepare_v2(c, "PRAGMA page_count", -1, &st, nullptr);
  const std::uint64_t n =
      sqlite3_step(st) == SQLITE_ROW ? static_cast<std::uint64_t>(sqlite3_column_int64(st, 0)) : 0;
  sqlite3_finalize(st);
  sqlite3_close(c);
  return n;
}

}  // namespace tocd::test

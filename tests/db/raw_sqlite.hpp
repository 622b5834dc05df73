#pragma once

// A database file as another program sees it: the SQLite C API called directly, independent of
// the code under test, to set up files tocdlab did not write and to check what it stored.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sqlite3.h>

namespace tocd::db::testing {

/// Runs `sql` (one or more statements) on the file at `path`, created when absent; returns
/// SQLite's error message, empty when every statement succeeded.
inline std::string raw_exec(const std::filesystem::path& path, const std::string& sql) {
  sqlite3* raw = nullptr;
  std::string error;
  if (sqlite3_open(path.c_str(), &raw) != SQLITE_OK) {
    error = raw ? sqlite3_errmsg(raw) : "out of memory";
  } else {
    char* err = nullptr;
    if (sqlite3_exec(raw, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK)
      error = err ? err : sqlite3_errmsg(raw);
    sqlite3_free(err);
  }
  sqlite3_close(raw);
  return error;
}

/// Calls `on_row(statement)` for each row of the query `sql` on the file at `path`, opened
/// read-only; a query that cannot be prepared is a test failure naming SQLite's message.
template <class OnRow>
void raw_for_each_row(const std::filesystem::path& path, const std::string& sql, OnRow on_row) {
  sqlite3* raw = nullptr;
  sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(raw, sql.c_str(), -1, &s, nullptr) != SQLITE_OK) {
    ADD_FAILURE() << sqlite3_errmsg(raw) << " in " << sql;
  } else {
    while (sqlite3_step(s) == SQLITE_ROW) on_row(s);
  }
  sqlite3_finalize(s);
  sqlite3_close(raw);
}

/// The rows of a query as text, NULL as "NULL".
inline std::vector<std::vector<std::string>> raw_rows(const std::filesystem::path& path,
                                                      const std::string& sql) {
  std::vector<std::vector<std::string>> out;
  raw_for_each_row(path, sql, [&](sqlite3_stmt* s) {
    std::vector<std::string> row;
    for (int i = 0; i < sqlite3_column_count(s); ++i) {
      const auto* t = sqlite3_column_text(s, i);
      row.push_back(t ? reinterpret_cast<const char*>(t) : "NULL");
    }
    out.push_back(std::move(row));
  });
  return out;
}

/// The first column of a query's first row as an integer; -1 when there is no row.
inline std::int64_t raw_int(const std::filesystem::path& path, const std::string& sql) {
  std::int64_t v = -1;
  bool first = true;
  raw_for_each_row(path, sql, [&](sqlite3_stmt* s) {
    if (first) v = sqlite3_column_int64(s, 0);
    first = false;
  });
  return v;
}

}  // namespace tocd::db::testing

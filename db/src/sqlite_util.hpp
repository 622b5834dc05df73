#pragma once

// Thin RAII layer over the SQLite C API: a connection, prepared statements, typed binds and
// column reads that turn SQL NULL into NaN / 0, and errors into DatabaseError.

#include <concepts>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <sqlite3.h>

#include "tocd/db/database.hpp"
#include "transaction.hpp"
#include "write_turns.hpp"

namespace tocd::db::detail {

/// Throws DatabaseError "<what>: <sqlite message>" for a failed call on `db`.
[[noreturn]] void fail(sqlite3* db, std::string_view what);

/// How long a connection waits for a lock another connection holds before it gives up.
inline constexpr int kBusyTimeoutMs = 10000;

class Connection {
 public:
  Connection() = default;
  /// sqlite3_open_v2 with `flags`; a busy timeout so short lock waits never surface as errors;
  /// SQLITE_DBCONFIG_DEFENSIVE on and trusted_schema off, as for any file of unknown origin.
  /// A read-write connection takes its turns at the write lock with the process's others
  /// (write_turns.hpp): its writes outside a transaction, and its BEGINs, say they wait.
  Connection(const std::filesystem::path& path, int flags, int busy_timeout_ms = kBusyTimeoutMs);
  ~Connection();
  Connection(Connection&& other) noexcept : db_(other.db_), turns_(std::move(other.turns_)) {
    other.db_ = nullptr;
  }
  Connection& operator=(Connection&& other) noexcept;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  sqlite3* get() const noexcept { return db_; }
  /// Runs one or more statements without results.
  void exec(const std::string& sql) const;
  /// First column of the first row of a query as an integer (0 when no row).
  std::int64_t query_int(const std::string& sql) const;
  /// For a connection that writes batch after batch: returns once no other connection of this
  /// process waits for the write lock (at most kBusyTimeoutMs, when such a waiter gives up).
  void let_waiting_writers_first() const;
  /// The turns this connection's writes take part in; null for a read-only connection.
  WriteTurns* turns() const noexcept { return turns_.get(); }

 private:
  sqlite3* db_ = nullptr;
  std::shared_ptr<WriteTurns> turns_;
};

/// Opens an existing file read-only. A WAL database in a directory this process may not write
/// cannot get its -shm index; it is then opened immutable (the main file alone) and `note`
/// says so, and what that leaves out. Otherwise `note` is left as it was.
Connection open_existing_read_only(const std::filesystem::path& path, std::string& note);

class Statement {
 public:
  Statement(const Connection& c, std::string_view sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // Binds are 1-based as in SQLite. NaN doubles bind NULL.
  Statement& bind(int i, std::int64_t v);
  template <std::integral T>
  requires(!std::same_as<T, std::int64_t> && !std::same_as<T, bool>) Statement& bind(int i, T v) {
    return bind(i, static_cast<std::int64_t>(v));
  }
  Statement& bind(int i, double v);
  Statement& bind(int i, std::string_view v);  // copied (SQLITE_TRANSIENT)
  Statement& bind_null(int i);
  /// Binds NULL for an id of 0 (no reference), else the id.
  Statement& bind_id(int i, std::int64_t id) { return id == 0 ? bind_null(i) : bind(i, id); }

  /// Steps once: true when a row is ready, false when done. Throws on error.
  bool step();
  /// Steps to completion (for statements without rows).
  void run();
  void reset();  // reset + clear bindings

  std::int64_t col_int(int i) const;  // NULL -> 0
  double col_double(int i) const;     // NULL -> NaN
  std::string col_text(int i) const;  // NULL -> ""
  bool col_null(int i) const;

  sqlite3_stmt* get() const noexcept { return stmt_; }

 private:
  sqlite3* db_ = nullptr;
  WriteTurns* turns_ = nullptr;
  sqlite3_stmt* stmt_ = nullptr;
};

/// The current row of a statement, read as record_rows.hpp reads a row of either backend.
class Row {
 public:
  explicit Row(const Statement& s) noexcept : s_(s) {}
  std::int64_t i64(int col) const { return s_.col_int(col); }
  double f64(int col) const { return s_.col_double(col); }
  std::string text(int col) const { return s_.col_text(col); }
  bool null(int col) const { return s_.col_null(col); }

 private:
  const Statement& s_;
};

/// How a query names its first parameter (read_run_rows writes its WHERE clause with it).
inline std::string run_id_parameter(const Connection&) {
  return "?";
}

/// Every row of `sql`, its one parameter bound to `key`, as `read(const Row&)` makes it.
template <class Read>
auto read_rows(const Connection& c, std::string_view sql, std::int64_t key, Read read) {
  Statement s(c, sql);
  s.bind(1, key);
  std::vector<decltype(read(Row(s)))> out;
  while (s.step()) out.push_back(read(Row(s)));
  return out;
}

/// ROLLBACK, its failure ignored: for a transaction given up (BasicTransaction's destructor).
void rollback_quietly(const Connection& c) noexcept;

/// BEGIN IMMEDIATE .. COMMIT, rolled back when destroyed without commit().
class Transaction : public BasicTransaction<Connection> {
 public:
  explicit Transaction(const Connection& c) : BasicTransaction(c, "BEGIN IMMEDIATE") {}
};

/// What SQLite's quick_check finds wrong with the file behind `c`: every page read once,
/// damaged b-trees and pages found (the full integrity_check also cross-checks indexes; on a
/// 100 MB file, warm cache, busy machine, quick_check took 0.7 s and integrity_check 4.8 s).
/// At most five problems, printable; empty when the file is sound.
std::vector<std::string> quick_check(const Connection& c);

}  // namespace tocd::db::detail

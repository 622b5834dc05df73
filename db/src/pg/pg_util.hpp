#pragma once

// Thin RAII layer over libpq: a connection, a query result with typed column reads (SQL NULL
// -> NaN / 0 / ""), parameters as text, COPY ... FROM STDIN, and errors as DatabaseError that
// name the server (its URI without a password) and what was being done.

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <libpq-fe.h>

#include "tocd/db/database.hpp"
#include "transaction.hpp"

namespace tocd::db::pg {

/// Text as a server database (UTF-8) can store it: every byte of an invalid UTF-8 sequence,
/// and NUL, becomes U+FFFD; valid text, control characters included, is kept as it is. An
/// SQLite file stores any bytes (an instrument's identity read before it was cleaned, a file
/// written by something else); the server refuses them, and a push must not fail on them.
std::string server_text(std::string_view v);

/// One query parameter in libpq's text format; NaN doubles and std::nullopt are NULL.
class Param {
 public:
  Param(std::nullopt_t) {}                                // NOLINT(google-explicit-constructor): NULL
  Param(std::int64_t v) : text_(std::to_string(v)) {}     // NOLINT
  Param(int v) : text_(std::to_string(v)) {}              // NOLINT
  Param(double v);                                        // NOLINT
  Param(std::string_view v) : text_(server_text(v)) {}    // NOLINT
  Param(const std::string& v) : text_(server_text(v)) {}  // NOLINT
  Param(const char* v) : text_(server_text(v)) {}         // NOLINT
  /// An id of 0 means "no reference": NULL.
  static Param id(std::int64_t v) { return v == 0 ? Param(std::nullopt) : Param(v); }
  const char* c_str() const noexcept { return text_ ? text_->c_str() : nullptr; }

 private:
  std::optional<std::string> text_;
};

class Result {
 public:
  explicit Result(PGresult* r) noexcept : r_(r) {}
  ~Result() { PQclear(r_); }
  Result(Result&& o) noexcept : r_(o.r_) { o.r_ = nullptr; }
  Result& operator=(Result&& o) noexcept;
  Result(const Result&) = delete;
  Result& operator=(const Result&) = delete;

  ExecStatusType status() const noexcept { return PQresultStatus(r_); }
  int rows() const noexcept { return PQntuples(r_); }
  bool null(int row, int col) const noexcept { return PQgetisnull(r_, row, col) != 0; }
  std::string text(int row, int col) const;  // NULL -> ""
  std::int64_t i64(int row, int col) const;  // NULL -> 0
  double f64(int row, int col) const;        // NULL -> NaN
  std::optional<std::int64_t> opt_i64(int row, int col) const;

 private:
  PGresult* r_ = nullptr;
};

/// Row `i` of a result, read as record_rows.hpp reads a row of either backend.
class Row {
 public:
  Row(const Result& r, int i) noexcept : r_(r), i_(i) {}
  std::int64_t i64(int col) const { return r_.i64(i_, col); }
  double f64(int col) const { return r_.f64(i_, col); }
  std::string text(int col) const { return r_.text(i_, col); }
  bool null(int col) const { return r_.null(i_, col); }

 private:
  const Result& r_;
  int i_;
};

class Connection {
 public:
  /// Connects to `uri` (libpq's environment, service file and ~/.pgpass fill in the rest).
  /// `read_only`: the session refuses every write (default_transaction_read_only).
  /// Throws DatabaseError naming the server when it cannot connect (down, refused, auth).
  explicit Connection(const std::string& uri, bool read_only = false);
  ~Connection();
  Connection(Connection&& o) noexcept : c_(o.c_), name_(std::move(o.name_)) { o.c_ = nullptr; }
  Connection& operator=(Connection&&) = delete;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  PGconn* get() const noexcept { return c_; }
  /// The server as messages name it (display_location of the URI).
  const std::string& name() const noexcept { return name_; }

  /// Runs one or more statements without parameters.
  void exec(const std::string& sql) const;
  /// Runs one statement with text parameters ($1, $2, ...); returns its rows.
  Result query(const std::string& sql, std::initializer_list<Param> params = {}) const;
  Result query(const std::string& sql, const std::vector<Param>& params) const;
  /// First column of the first row as an integer (0 when no row or NULL).
  std::int64_t query_int(const std::string& sql, std::initializer_list<Param> params = {}) const;
  /// `COPY table(columns) FROM STDIN` with `data` in COPY's text format (tab-separated, one
  /// row per line, \N for NULL).
  void copy_in(const std::string& copy_sql, std::string_view data) const;

  /// Throws DatabaseError "<server>: <what>: <libpq message>".
  [[noreturn]] void fail(std::string_view what) const;

 private:
  PGconn* c_ = nullptr;
  std::string name_;
};

/// How a query names its first parameter (read_run_rows writes its WHERE clause with it).
inline std::string run_id_parameter(const Connection&) {
  return "$1";
}

/// Every row of `sql`, its parameter $1 set to `key`, as `read(const Row&)` makes it.
template <class Read>
auto read_rows(const Connection& c, const std::string& sql, std::int64_t key, Read read) {
  const Result r = c.query(sql, {key});
  std::vector<decltype(read(Row(r, 0)))> out;
  out.reserve(static_cast<std::size_t>(r.rows()));
  for (int i = 0; i < r.rows(); ++i) out.push_back(read(Row(r, i)));
  return out;
}

/// ROLLBACK, its failure ignored: for a transaction given up (BasicTransaction's destructor).
void rollback_quietly(const Connection& c) noexcept;

/// BEGIN (or `begin`, e.g. with an isolation level) .. COMMIT, rolled back when destroyed
/// without commit().
class Transaction : public detail::BasicTransaction<Connection> {
 public:
  explicit Transaction(const Connection& c, const char* begin = "BEGIN") : BasicTransaction(c, begin) {}
};

/// A value in COPY's text format: NULL for NaN, shortest round-trip digits otherwise.
void append_copy_value(std::string& out, double v);
void append_copy_value(std::string& out, std::int64_t v);
/// Text with COPY's escapes (backslash, tab, newline, carriage return).
void append_copy_text(std::string& out, std::string_view v);

}  // namespace tocd::db::pg

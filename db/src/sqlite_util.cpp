#include "sqlite_util.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <system_error>

#include "tocd/core/printable.hpp"

namespace tocd::db::detail {

void fail(sqlite3* db, std::string_view what) {
  throw DatabaseError(std::string(what) + ": " + (db ? sqlite3_errmsg(db) : "out of memory"));
}

Connection::Connection(const std::filesystem::path& path, int flags, int busy_timeout_ms) {
  const int rc = sqlite3_open_v2(path.c_str(), &db_, flags, nullptr);
  if (rc != SQLITE_OK) {
    const std::string msg = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
    sqlite3_close(db_);
    db_ = nullptr;
    throw DatabaseError("cannot open database '" + path.string() + "': " + msg);
  }
  sqlite3_extended_result_codes(db_, 1);
  sqlite3_busy_timeout(db_, busy_timeout_ms);
  // Database files come from anywhere (a colleague, a download): SQLite's defensive mode
  // refuses schema edits that can corrupt a file on purpose, and with trusted_schema off a
  // view or trigger planted in the file cannot call functions with side effects.
  int defensive = 0;
  if (sqlite3_db_config(db_, SQLITE_DBCONFIG_DEFENSIVE, 1, &defensive) != SQLITE_OK || defensive != 1 ||
      sqlite3_exec(db_, "PRAGMA trusted_schema=OFF", nullptr, nullptr, nullptr) != SQLITE_OK) {
    const std::string msg = sqlite3_errmsg(db_);
    sqlite3_close(db_);
    db_ = nullptr;
    throw DatabaseError("cannot open database '" + path.string() + "' in defensive mode: " + msg);
  }
  if ((flags & SQLITE_OPEN_READWRITE) != 0) turns_ = WriteTurns::of(path);
}

Connection::~Connection() {
  sqlite3_close_v2(db_);
}

Connection& Connection::operator=(Connection&& other) noexcept {
  if (this != &other) {
    sqlite3_close_v2(db_);
    db_ = other.db_;
    other.db_ = nullptr;
    turns_ = std::move(other.turns_);
  }
  return *this;
}

void Connection::exec(const std::string& sql) const {
  char* err = nullptr;
  // Outside a transaction a statement here may take the write lock (BEGIN IMMEDIATE, a PRAGMA
  // that writes); inside one, this connection holds whatever lock it needs already.
  const WriteTurns::Waiting waiting(sqlite3_get_autocommit(db_) != 0 ? turns_.get() : nullptr);
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    std::string msg = err ? err : sqlite3_errmsg(db_);
    sqlite3_free(err);
    throw DatabaseError("database statement failed (" + sql.substr(0, 60) + "): " + msg);
  }
}

namespace {

// A file: URI for `path` (RFC 3986 escapes for everything but unreserved characters and '/').
std::string file_uri(const std::filesystem::path& path) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out = "file:";
  for (const unsigned char c : std::filesystem::absolute(path).string()) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '.' || c == '_' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 0xF];
    }
  }
  return out;
}

}  // namespace

Connection open_existing_read_only(const std::filesystem::path& path, std::string& note) {
  Connection c(path, SQLITE_OPEN_READONLY);
  // SQLite opens lazily: the first read shows whether the file can be read at all.
  if (sqlite3_exec(c.get(), "SELECT count(*) FROM sqlite_master", nullptr, nullptr, nullptr) == SQLITE_OK)
    return c;
  const int primary = sqlite3_extended_errcode(c.get()) & 0xFF;
  if (primary != SQLITE_READONLY && primary != SQLITE_CANTOPEN) return c;  // the caller reports it
  // A WAL database needs its -shm index file, which a reader cannot create in a directory it
  // may not write. immutable=1 reads the main file alone; nothing can be writing it there.
  Connection immutable(file_uri(path) + "?mode=ro&immutable=1", SQLITE_OPEN_READONLY | SQLITE_OPEN_URI);
  std::error_code ec;
  const auto wal = std::filesystem::path(path.string() + "-wal");
  const auto wal_bytes = std::filesystem::exists(wal, ec) ? std::filesystem::file_size(wal, ec) : 0;
  note = "'" + path.string() +
         "' was opened read-only as it stands: its directory is not writable, so SQLite " +
         "cannot create the WAL index beside it";
  if (!ec && wal_bytes > 0)
    note += "; the " + std::to_string(wal_bytes) + "-byte write-ahead log beside it was not read, so its " +
            "last commits are missing";
  return immutable;
}

void Connection::let_waiting_writers_first() const {
  if (turns_) turns_->let_waiting_writers_first(std::chrono::milliseconds(kBusyTimeoutMs));
}

std::int64_t Connection::query_int(const std::string& sql) const {
  Statement s(*this, sql);
  return s.step() ? s.col_int(0) : 0;
}

Statement::Statement(const Connection& c, std::string_view sql) : db_(c.get()), turns_(c.turns()) {
  if (sqlite3_prepare_v2(db_, sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr) != SQLITE_OK)
    fail(db_, "cannot prepare '" + std::string(sql.substr(0, 60)) + "'");
}

Statement::~Statement() {
  sqlite3_finalize(stmt_);
}

Statement& Statement::bind(int i, std::int64_t v) {
  if (sqlite3_bind_int64(stmt_, i, v) != SQLITE_OK) fail(db_, "bind");
  return *this;
}

Statement& Statement::bind(int i, double v) {
  if (std::isnan(v)) return bind_null(i);
  if (sqlite3_bind_double(stmt_, i, v) != SQLITE_OK) fail(db_, "bind");
  return *this;
}

Statement& Statement::bind(int i, std::string_view v) {
  if (sqlite3_bind_text64(stmt_, i, v.data(), v.size(), SQLITE_TRANSIENT, SQLITE_UTF8) != SQLITE_OK)
    fail(db_, "bind");
  return *this;
}

Statement& Statement::bind_null(int i) {
  if (sqlite3_bind_null(stmt_, i) != SQLITE_OK) fail(db_, "bind");
  return *this;
}

bool Statement::step() {
  // A write outside a transaction takes the write lock for itself: it waits its turn.
  const bool takes_lock = turns_ && sqlite3_get_autocommit(db_) != 0 && sqlite3_stmt_readonly(stmt_) == 0;
  const WriteTurns::Waiting waiting(takes_lock ? turns_ : nullptr);
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  const std::string sql = sqlite3_sql(stmt_) ? sqlite3_sql(stmt_) : "";
  sqlite3_reset(stmt_);
  fail(db_, "database statement failed (" + sql.substr(0, 60) + ")");
}

void Statement::run() {
  while (step()) {
  }
}

void Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

std::int64_t Statement::col_int(int i) const {
  return sqlite3_column_int64(stmt_, i);
}

double Statement::col_double(int i) const {
  return col_null(i) ? std::nan("") : sqlite3_column_double(stmt_, i);
}

std::string Statement::col_text(int i) const {
  const auto* p = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, i));
  return p ? std::string(p, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, i))) : std::string();
}

bool Statement::col_null(int i) const {
  return sqlite3_column_type(stmt_, i) == SQLITE_NULL;
}

void rollback_quietly(const Connection& c) noexcept {
  sqlite3_exec(c.get(), "ROLLBACK", nullptr, nullptr, nullptr);
}

std::vector<std::string> quick_check(const Connection& c) {
  std::vector<std::string> found;
  try {
    Statement s(c, "PRAGMA quick_check(5)");
    // One row per problem, though SQLite packs several lines into the first row.
    while (s.step()) {
      const std::string row = s.col_text(0);
      for (std::size_t start = 0; start <= row.size();) {
        const auto end = std::min(row.find('\n', start), row.size());
        if (end > start) found.push_back(row.substr(start, end - start));
        start = end + 1;
      }
    }
  } catch (const DatabaseError& e) {
    found.push_back(e.what());
  }
  if (found.size() == 1 && found[0] == "ok") return {};
  for (auto& f : found) f = printable_text(f);
  return found;
}

}  // namespace tocd::db::detail

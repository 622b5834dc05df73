#include "pg_util.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <string>

#include <fmt/format.h>

#include "tocd/db/location.hpp"

namespace tocd::db::pg {

namespace {

std::string trimmed(const char* message) {
  std::string s = message ? message : "";
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  // libpq repeats "connection to server at ... failed:" per address tried; the lines after
  // the first say the same thing for the next address.
  for (auto& ch : s)
    if (ch == '\n') ch = ' ';
  return s;
}

}  // namespace

namespace {

// Length of the valid UTF-8 sequence at the start of `v` (1 to 4), or 0 when it is invalid
// (a stray continuation byte, an overlong form, a surrogate, beyond U+10FFFF, truncated).
std::size_t utf8_length(std::string_view v) {
  const auto b = [&](std::size_t i) { return static_cast<unsigned char>(v[i]); };
  const unsigned char c = b(0);
  if (c < 0x80) return c == 0 ? 0 : 1;
  std::size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (v.size() < n || b(1) < lo || b(1) > hi) return 0;
  for (std::size_t i = 2; i < n; ++i)
    if (b(i) < 0x80 || b(i) > 0xBF) return 0;
  return n;
}

}  // namespace

std::string server_text(std::string_view v) {
  std::string out;
  out.reserve(v.size());
  while (!v.empty()) {
    const std::size_t n = utf8_length(v);
    if (n == 0) {
      out += "\xEF\xBF\xBD";
      v.remove_prefix(1);
    } else {
      out.append(v.substr(0, n));
      v.remove_prefix(n);
    }
  }
  return out;
}

Param::Param(double v) {
  if (!std::isnan(v)) text_ = fmt::format("{}", v);  // shortest round-trip, "inf" as Infinity
  if (text_ && std::isinf(v)) text_ = v > 0 ? "Infinity" : "-Infinity";
}

Result& Result::operator=(Result&& o) noexcept {
  if (this != &o) {
    PQclear(r_);
    r_ = o.r_;
    o.r_ = nullptr;
  }
  return *this;
}

std::string Result::text(int row, int col) const {
  return null(row, col) ? std::string() : std::string(PQgetvalue(r_, row, col));
}

std::int64_t Result::i64(int row, int col) const {
  return null(row, col) ? 0 : std::strtoll(PQgetvalue(r_, row, col), nullptr, 10);
}

double Result::f64(int row, int col) const {
  if (null(row, col)) return std::nan("");
  const char* v = PQgetvalue(r_, row, col);
  if (std::string_view(v) == "Infinity") return HUGE_VAL;
  if (std::string_view(v) == "-Infinity") return -HUGE_VAL;
  return std::strtod(v, nullptr);
}

std::optional<std::int64_t> Result::opt_i64(int row, int col) const {
  if (null(row, col)) return std::nullopt;
  return i64(row, col);
}

Connection::Connection(const std::string& uri, bool read_only) : name_(display_location(uri)) {
  // Defaults that keep a dead or unreachable server from hanging a command: a connect timeout
  // and TCP keepalives (libpq waits forever without them). Given before the URI, so that
  // settings in the URI or the environment win.
  std::vector<const char*> keys, values;
  const auto set_default = [&](const char* key, const char* env, const char* value) {
    if (env && std::getenv(env)) return;
    keys.push_back(key);
    values.push_back(value);
  };
  set_default("connect_timeout", "PGCONNECT_TIMEOUT", "10");
  set_default("keepalives_idle", nullptr, "10");
  set_default("keepalives_interval", nullptr, "5");
  set_default("keepalives_count", nullptr, "3");
  set_default("application_name", "PGAPPNAME", "tocdlab");
  keys.push_back("dbname");
  values.push_back(uri.c_str());
  keys.push_back(nullptr);
  values.push_back(nullptr);
  c_ = PQconnectdbParams(keys.data(), values.data(), 1);
  if (!c_) throw DatabaseError(fmt::format("cannot connect to PostgreSQL at '{}': out of memory", name_));
  if (PQstatus(c_) != CONNECTION_OK) {
    const std::string why = trimmed(PQerrorMessage(c_));
    PQfinish(c_);
    c_ = nullptr;
    throw DatabaseError(fmt::format("cannot connect to PostgreSQL at '{}': {}", name_, why));
  }
  // Notices (e.g. "relation already exists, skipping") are not for a lab user's terminal.
  PQsetNoticeProcessor(
      c_, [](void*, const char*) {}, nullptr);
  exec("SET client_min_messages = warning; SET TIME ZONE 'UTC'");
  if (read_only) exec("SET default_transaction_read_only = on");
}

Connection::~Connection() {
  if (c_) PQfinish(c_);
}

void Connection::fail(std::string_view what) const {
  throw DatabaseError(fmt::format("PostgreSQL at '{}': {}: {}", name_, what, trimmed(PQerrorMessage(c_))));
}

namespace {

bool ok(const Result& r) {
  const auto st = r.status();
  return st == PGRES_COMMAND_OK || st == PGRES_TUPLES_OK || st == PGRES_COPY_IN;
}

std::string first_line(std::string_view sql) {
  std::string s(sql.substr(0, sql.find('\n')));
  return s.size() > 60 ? s.substr(0, 60) + "..." : s;
}

}  // namespace

void Connection::exec(const std::string& sql) const {
  Result r(PQexec(c_, sql.c_str()));
  if (!ok(r)) fail(first_line(sql));
}

Result Connection::query(const std::string& sql, std::initializer_list<Param> params) const {
  return query(sql, std::vector<Param>(params));
}

Result Connection::query(const std::string& sql, const std::vector<Param>& params) const {
  std::vector<const char*> values;
  values.reserve(params.size());
  for (const auto& p : params) values.push_back(p.c_str());
  Result r(PQexecParams(c_, sql.c_str(), static_cast<int>(values.size()), nullptr, values.data(), nullptr,
                        nullptr, 0));
  if (!ok(r)) fail(first_line(sql));
  return r;
}

std::int64_t Connection::query_int(const std::string& sql, std::initializer_list<Param> params) const {
  const Result r = query(sql, params);
  return r.rows() > 0 ? r.i64(0, 0) : 0;
}

void Connection::copy_in(const std::string& copy_sql, std::string_view data) const {
  Result start(PQexec(c_, copy_sql.c_str()));
  if (start.status() != PGRES_COPY_IN) fail(first_line(copy_sql));
  // libpq buffers; large chunks keep the number of calls (and of network packets) low.
  constexpr std::size_t kChunk = 1 << 20;
  for (std::size_t from = 0; from < data.size(); from += kChunk) {
    const auto n = std::min(kChunk, data.size() - from);
    if (PQputCopyData(c_, data.data() + from, static_cast<int>(n)) != 1) fail("sending COPY data");
  }
  if (PQputCopyEnd(c_, nullptr) != 1) fail("ending COPY");
  for (PGresult* raw = PQgetResult(c_); raw; raw = PQgetResult(c_)) {
    Result r(raw);
    if (r.status() != PGRES_COMMAND_OK) fail(first_line(copy_sql));
  }
}

void rollback_quietly(const Connection& c) noexcept {
  // Best effort: a lost connection has rolled back already.
  Result r(PQexec(c.get(), "ROLLBACK"));
}

void append_copy_value(std::string& out, double v) {
  if (std::isnan(v)) {
    out += "\\N";
    return;
  }
  if (std::isinf(v)) {
    out += v > 0 ? "Infinity" : "-Infinity";
    return;
  }
  fmt::format_to(std::back_inserter(out), "{}", v);
}

void append_copy_value(std::string& out, std::int64_t v) {
  fmt::format_to(std::back_inserter(out), "{}", v);
}

void append_copy_text(std::string& out, std::string_view v) {
  for (char ch : server_text(v)) {
    switch (ch) {
      case '\\':
        out += "\\\\";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        out += ch;
    }
  }
}

}  // namespace tocd::db::pg

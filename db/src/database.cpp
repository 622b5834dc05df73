#include "tocd/db/database.hpp"

#include <string>

#include <sqlite3.h>

namespace tocd::db {

namespace {
constexpr int kSchemaVersion = 1;
}

struct Database::Impl {
  sqlite3* handle = nullptr;
  ~Impl() { sqlite3_close(handle); }
};

Database::Database(const std::filesystem::path& path) : impl_(std::make_unique<Impl>()) {
  if (sqlite3_open(path.c_str(), &impl_->handle) != SQLITE_OK) {
    throw DatabaseError("cannot open database '" + path.string() + "': " + sqlite3_errmsg(impl_->handle));
  }
  if (schema_version() == 0) {
    const std::string sql = "PRAGMA user_version = " + std::to_string(kSchemaVersion);
    sqlite3_exec(impl_->handle, sql.c_str(), nullptr, nullptr, nullptr);
  }
}

Database::~Database() = default;

int Database::schema_version() const {
  sqlite3_stmt* stmt = nullptr;
  if (sqlite3_prepare_v2(impl_->handle, "PRAGMA user_version", -1, &stmt, nullptr) != SQLITE_OK) {
    throw DatabaseError(std::string("cannot read schema version: ") + sqlite3_errmsg(impl_->handle));
  }
  int version = -1;
  if (sqlite3_step(stmt) == SQLITE_ROW) version = sqlite3_column_int(stmt, 0);
  sqlite3_finalize(stmt);
  return version;
}

}  // namespace tocd::db

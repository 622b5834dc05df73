#pragma once

#include <filesystem>
#include <memory>

#include "tocd/core/error.hpp"

namespace tocd::db {

/// A database file that cannot be opened or is not a tocdlab database.
class DatabaseError : public Error {
 public:
  using Error::Error;
};

/// One tocdlab measurement database file (SQLite).
class Database {
 public:
  /// Opens (creating when absent) the database at `path` and brings its schema up to date.
  explicit Database(const std::filesystem::path& path);
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  /// The schema version stored in the file (PRAGMA user_version).
  int schema_version() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tocd::db

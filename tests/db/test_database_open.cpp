// Opening files: new files get the current schema; foreign, corrupt-looking and newer-schema
// files are refused with a clear message and left byte-for-byte untouched.
#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include "temp_dir.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/writer.hpp"

namespace {

using ::testing::HasSubstr;
using tocd::db::Database;
using tocd::db::DatabaseError;
using tocd::db::testing::file_bytes;
using tocd::db::testing::TempDir;

std::string error_of(const std::filesystem::path& p) {
  try {
    Database db(p);
  } catch (const DatabaseError& e) {
    return e.what();
  }
  return "";
}

// Creates an SQLite file with the raw C API (as another application would).
void make_sqlite(const std::filesystem::path& p, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(p.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
  sqlite3_close(db);
}

std::int64_t pragma(const std::filesystem::path& p, const std::string& name) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(p.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(db, ("PRAGMA " + name).c_str(), -1, &s, nullptr);
  std::int64_t v = -1;
  if (sqlite3_step(s) == SQLITE_ROW) v = sqlite3_column_int64(s, 0);
  sqlite3_finalize(s);
  sqlite3_close(db);
  return v;
}

TEST(DbOpen, NewFileGetsCurrentSchemaIdentityAndWal) {
  TempDir dir;
  const auto path = dir / "lab.sqlite";
  {
    Database db = Database::open(path);
    EXPECT_EQ(db.schema_version(), Database::kSchemaVersion);
    EXPECT_EQ(db.integrity_check(), "ok");
    EXPECT_TRUE(db.interrupted_on_open().empty());
    // WAL while a writer has it open: readers and the writer never block each other.
    EXPECT_EQ(db.journal_mode(), "wal");
  }
  EXPECT_EQ(pragma(path, "user_version"), Database::kSchemaVersion);
  EXPECT_EQ(pragma(path, "application_id"), Database::kApplicationId);
  // At rest (the last writer closed) the file is in rollback mode, one file: a reader, which
  // opens it read-only, finds no WAL and leaves no -wal and -shm beside it.
  {
    const tocd::db::Reader r(path);
    EXPECT_TRUE(r.runs().empty());
  }
  EXPECT_FALSE(std::filesystem::exists(path.string() + "-wal"));
  EXPECT_FALSE(std::filesystem::exists(path.string() + "-shm"));
  sqlite3* raw = nullptr;
  sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(raw, "PRAGMA journal_mode", -1, &s, nullptr);
  ASSERT_EQ(sqlite3_step(s), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(s, 0)), "delete");
  sqlite3_finalize(s);
  sqlite3_close(raw);
  // Reopening is a no-op migration, keeps the version and turns WAL on again.
  Database again(path);
  EXPECT_EQ(again.schema_version(), Database::kSchemaVersion);
  EXPECT_EQ(again.journal_mode(), "wal");
}

TEST(DbOpen, EveryDocumentedTableExists) {
  TempDir dir;
  const auto path = dir / "lab.sqlite";
  { Database db(path); }
  for (const char* table : {"meta", "instruments", "specimens", "runs", "run_anchors", "channels", "samples",
                            "steps", "step_channel_stats", "events", "predictions"}) {
    sqlite3* raw = nullptr;
    sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
    sqlite3_stmt* s = nullptr;
    sqlite3_prepare_v2(raw, "SELECT count(*) FROM sqlite_master WHERE type='table' AND name=?", -1, &s,
                       nullptr);
    sqlite3_bind_text(s, 1, table, -1, SQLITE_STATIC);
    ASSERT_EQ(sqlite3_step(s), SQLITE_ROW);
    EXPECT_EQ(sqlite3_column_int(s, 0), 1) << table;
    sqlite3_finalize(s);
    sqlite3_close(raw);
  }
}

TEST(DbOpen, EmptyFileAndEmptySqliteFileAreInitialised) {
  TempDir dir;
  const auto empty = dir / "empty.sqlite";
  std::ofstream(empty).close();
  EXPECT_EQ(Database(empty).schema_version(), Database::kSchemaVersion);
  const auto blank = dir / "blank.sqlite";
  make_sqlite(blank, "PRAGMA user_version = 0");
  EXPECT_EQ(Database(blank).schema_version(), Database::kSchemaVersion);
}

TEST(DbOpen, PartlyInitialisedTocdlabFileIsMigrated) {
  // application_id set, user_version 0 (e.g. a creation cut off before the first migration).
  TempDir dir;
  const auto path = dir / "partial.sqlite";
  make_sqlite(path, "PRAGMA application_id = " + std::to_string(Database::kApplicationId));
  Database db(path);
  EXPECT_EQ(db.schema_version(), Database::kSchemaVersion);
  EXPECT_EQ(db.integrity_check(), "ok");
}

TEST(DbOpen, TextFileIsRefusedAndUntouched) {
  TempDir dir;
  const auto path = dir / "notes.sqlite";
  std::ofstream(path) << "step,load\n1,2.5\n this is a CSV, not a database\n";
  const std::string before = file_bytes(path);
  const std::string msg = error_of(path);
  EXPECT_THAT(msg, HasSubstr("is not a tocdlab database"));
  EXPECT_THAT(msg, HasSubstr(path.string()));
  EXPECT_EQ(file_bytes(path), before);
  EXPECT_FALSE(std::filesystem::exists(path.string() + "-wal"));
  EXPECT_THROW(tocd::db::Reader{path}, DatabaseError);
  EXPECT_THROW(tocd::db::Writer{path}, DatabaseError);
  EXPECT_EQ(file_bytes(path), before);
}

TEST(DbOpen, OtherApplicationsSqliteFileIsRefusedAndUntouched) {
  TempDir dir;
  const auto path = dir / "other.sqlite";
  make_sqlite(path,
              "CREATE TABLE photos(id INTEGER PRIMARY KEY, name TEXT); INSERT INTO photos VALUES(1, 'a');");
  const std::string before = file_bytes(path);
  const std::string msg = error_of(path);
  EXPECT_THAT(msg, HasSubstr("SQLite database of another application"));
  EXPECT_THAT(msg, HasSubstr("left untouched"));
  EXPECT_EQ(file_bytes(path), before);
  // Also with a foreign application id and no tables.
  const auto tagged = dir / "tagged.sqlite";
  make_sqlite(tagged, "PRAGMA application_id = 1234");
  const std::string tagged_before = file_bytes(tagged);
  EXPECT_THAT(error_of(tagged), HasSubstr("application_id 0x000004D2"));
  EXPECT_EQ(file_bytes(tagged), tagged_before);
}

TEST(DbOpen, NewerSchemaIsRefusedAndUntouched) {
  TempDir dir;
  const auto path = dir / "future.sqlite";
  { Database db(path); }
  make_sqlite(path, "PRAGMA user_version = " + std::to_string(Database::kSchemaVersion + 7));
  const std::string before = file_bytes(path);
  const std::string msg = error_of(path);
  EXPECT_THAT(msg, HasSubstr("newer tocdlab"));
  EXPECT_THAT(msg, HasSubstr("schema version " + std::to_string(Database::kSchemaVersion + 7)));
  EXPECT_EQ(file_bytes(path), before);
  EXPECT_THROW(tocd::db::Reader{path}, DatabaseError);
  EXPECT_THROW(tocd::db::Writer{path}, DatabaseError);
  EXPECT_EQ(file_bytes(path), before);
}

TEST(DbOpen, UnopenablePathsAreDatabaseErrors) {
  EXPECT_THROW(Database("/nonexistent-dir/x/y.sqlite"), DatabaseError);
  TempDir dir;
  EXPECT_THAT(error_of(dir.path()), HasSubstr("not a regular file"));
  EXPECT_THROW(tocd::db::Reader{dir / "absent.sqlite"}, DatabaseError);
  EXPECT_FALSE(std::filesystem::exists(dir / "absent.sqlite"));
}

}  // namespace

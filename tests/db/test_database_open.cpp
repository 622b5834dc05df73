// Opening files: new files get the current schema; foreign, corrupt-looking and newer-schema
// files are refused with a clear message and left byte-for-byte untouched.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "raw_sqlite.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/writer.hpp"
#include "tocd/test/error_of.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/temp_dir.hpp"

namespace {

using ::testing::HasSubstr;
using tocd::db::Database;
using tocd::db::DatabaseError;
using tocd::db::testing::raw_int;
using tocd::db::testing::raw_rows;
using tocd::test::read_file;
using tocd::test::TempDir;
using tocd::test::write_file;

std::string error_of(const std::filesystem::path& p) {
  return tocd::test::error_of<DatabaseError>([&] { Database db(p); });
}

// Creates an SQLite file with the raw C API (as another application would).
void make_sqlite(const std::filesystem::path& p, const std::string& sql) {
  ASSERT_EQ(tocd::db::testing::raw_exec(p, sql), "");
}

std::int64_t pragma(const std::filesystem::path& p, const std::string& name) {
  return raw_int(p, "PRAGMA " + name);
}

// Each test opens files of its own in a fresh folder.
class DbOpen : public ::testing::Test {
 protected:
  const TempDir dir_{"db_open"};
};

TEST_F(DbOpen, NewFileGetsCurrentSchemaIdentityAndWal) {
  const auto path = dir_ / "lab.sqlite";
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
  EXPECT_EQ(raw_rows(path, "PRAGMA journal_mode"), (std::vector<std::vector<std::string>>{{"delete"}}));
  // Reopening is a no-op migration, keeps the version and turns WAL on again.
  Database again(path);
  EXPECT_EQ(again.schema_version(), Database::kSchemaVersion);
  EXPECT_EQ(again.journal_mode(), "wal");
}

TEST_F(DbOpen, EveryDocumentedTableExists) {
  const auto path = dir_ / "lab.sqlite";
  { Database db(path); }
  for (const char* table : {"meta", "instruments", "specimens", "runs", "run_anchors", "channels", "samples",
                            "steps", "step_channel_stats", "events", "predictions"}) {
    EXPECT_EQ(raw_int(path, std::string("SELECT count(*) FROM sqlite_master WHERE type='table' AND name='") +
                                table + "'"),
              1)
        << table;
  }
}

TEST_F(DbOpen, EmptyFileAndEmptySqliteFileAreInitialised) {
  const auto empty = dir_ / "empty.sqlite";
  ASSERT_TRUE(write_file(empty, ""));
  EXPECT_EQ(Database(empty).schema_version(), Database::kSchemaVersion);
  const auto blank = dir_ / "blank.sqlite";
  make_sqlite(blank, "PRAGMA user_version = 0");
  EXPECT_EQ(Database(blank).schema_version(), Database::kSchemaVersion);
}

TEST_F(DbOpen, PartlyInitialisedTocdlabFileIsMigrated) {
  // application_id set, user_version 0 (e.g. a creation cut off before the first migration).
  const auto path = dir_ / "partial.sqlite";
  make_sqlite(path, "PRAGMA application_id = " + std::to_string(Database::kApplicationId));
  Database db(path);
  EXPECT_EQ(db.schema_version(), Database::kSchemaVersion);
  EXPECT_EQ(db.integrity_check(), "ok");
}

// A file of schema 3 (made here as this build's file without the column that migration 4
// adds) is upgraded when opened for writing: predictions.latency_s appears, NULL for the
// predictions stored before, which read back with the latency unset, never 0.
TEST_F(DbOpen, SchemaThreeFileGainsPredictionLatencyAsNull) {
  const auto path = dir_ / "v3.sqlite";
  std::int64_t run_id = 0;
  {
    Database db(path);
    tocd::db::NewRun nr;
    nr.protocol_text = "name = \"v3\"\n";
    run_id = db.create_run(nr).id;
    tocd::db::PredictionRecord p;
    p.run_id = run_id;
    p.config_json = "{}";
    p.T = 0.4;
    p.total_seconds = 2.0;
    db.add_prediction(p);
  }
  make_sqlite(path,
              "ALTER TABLE predictions DROP COLUMN latency_s; PRAGMA user_version = 3; "
              "UPDATE meta SET value = '3' WHERE key = 'schema_version'");
  const std::string has_latency =
      "SELECT count(*) FROM pragma_table_info('predictions') WHERE name = 'latency_s'";
  ASSERT_EQ(raw_int(path, has_latency), 0);
  // Readers never migrate: they ask for the upgrade.
  EXPECT_THAT(tocd::test::error_of<DatabaseError>([&] { tocd::db::Reader r(path); }),
              HasSubstr("schema version 3"));

  EXPECT_EQ(Database(path).schema_version(), Database::kSchemaVersion);
  EXPECT_EQ(pragma(path, "user_version"), 4);
  EXPECT_EQ(raw_int(path, has_latency), 1);
  EXPECT_EQ(raw_rows(path, "SELECT latency_s FROM predictions"),
            (std::vector<std::vector<std::string>>{{"NULL"}}));
  EXPECT_EQ(raw_rows(path, "SELECT value FROM meta WHERE key = 'schema_version'"),
            (std::vector<std::vector<std::string>>{{"4"}}));
  const auto preds = tocd::db::Reader(path).predictions(run_id);
  ASSERT_EQ(preds.size(), 1u);
  EXPECT_DOUBLE_EQ(preds[0].T, 0.4);
  EXPECT_DOUBLE_EQ(preds[0].total_seconds, 2.0);
  EXPECT_TRUE(std::isnan(preds[0].latency_s)) << preds[0].latency_s;
}

TEST_F(DbOpen, TextFileIsRefusedAndUntouched) {
  const auto path = dir_ / "notes.sqlite";
  ASSERT_TRUE(write_file(path, "step,load\n1,2.5\n this is a CSV, not a database\n"));
  const std::string before = read_file(path);
  const std::string msg = error_of(path);
  EXPECT_THAT(msg, HasSubstr("is not a tocdlab database"));
  EXPECT_THAT(msg, HasSubstr(path.string()));
  EXPECT_EQ(read_file(path), before);
  EXPECT_FALSE(std::filesystem::exists(path.string() + "-wal"));
  EXPECT_THROW(tocd::db::Reader{path}, DatabaseError);
  EXPECT_THROW(tocd::db::Writer{path}, DatabaseError);
  EXPECT_EQ(read_file(path), before);
}

TEST_F(DbOpen, OtherApplicationsSqliteFileIsRefusedAndUntouched) {
  const auto path = dir_ / "other.sqlite";
  make_sqlite(path,
              "CREATE TABLE photos(id INTEGER PRIMARY KEY, name TEXT); INSERT INTO photos VALUES(1, 'a');");
  const std::string before = read_file(path);
  const std::string msg = error_of(path);
  EXPECT_THAT(msg, HasSubstr("SQLite database of another application"));
  EXPECT_THAT(msg, HasSubstr("left untouched"));
  EXPECT_EQ(read_file(path), before);
  // Also with a foreign application id and no tables.
  const auto tagged = dir_ / "tagged.sqlite";
  make_sqlite(tagged, "PRAGMA application_id = 1234");
  const std::string tagged_before = read_file(tagged);
  EXPECT_THAT(error_of(tagged), HasSubstr("application_id 0x000004D2"));
  EXPECT_EQ(read_file(tagged), tagged_before);
}

TEST_F(DbOpen, NewerSchemaIsRefusedAndUntouched) {
  const auto path = dir_ / "future.sqlite";
  { Database db(path); }
  make_sqlite(path, "PRAGMA user_version = " + std::to_string(Database::kSchemaVersion + 7));
  const std::string before = read_file(path);
  const std::string msg = error_of(path);
  EXPECT_THAT(msg, HasSubstr("newer tocdlab"));
  EXPECT_THAT(msg, HasSubstr("schema version " + std::to_string(Database::kSchemaVersion + 7)));
  EXPECT_EQ(read_file(path), before);
  EXPECT_THROW(tocd::db::Reader{path}, DatabaseError);
  EXPECT_THROW(tocd::db::Writer{path}, DatabaseError);
  EXPECT_EQ(read_file(path), before);
}

TEST_F(DbOpen, UnopenablePathsAreDatabaseErrors) {
  EXPECT_THROW(Database("/nonexistent-dir/x/y.sqlite"), DatabaseError);
  EXPECT_THAT(error_of(dir_.path()), HasSubstr("not a regular file"));
  EXPECT_THROW(tocd::db::Reader{dir_ / "absent.sqlite"}, DatabaseError);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "absent.sqlite"));
}

}  // namespace

#include <filesystem>

#include <gtest/gtest.h>

#include "tocd/db/database.hpp"

TEST(Database, NewFileGetsCurrentSchemaAndKeepsIt) {
  const auto path = std::filesystem::temp_directory_path() / "tocd_test_db_open.sqlite";
  std::filesystem::remove(path);
  {
    tocd::db::Database db(path);
    EXPECT_GE(db.schema_version(), 1);
  }
  EXPECT_TRUE(std::filesystem::exists(path));
  tocd::db::Database reopened(path);
  EXPECT_GE(reopened.schema_version(), 1);
  std::filesystem::remove(path);
}

TEST(Database, UnopenablePathIsADatabaseError) {
  EXPECT_THROW(tocd::db::Database("/nonexistent-dir/x/y.sqlite"), tocd::db::DatabaseError);
}

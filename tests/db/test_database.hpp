#pragma once

// Where a database contract test records: a fresh SQLite file in a temporary directory, or,
// in the test binaries built with TOCD_DB_TEST_SERVER (the `*_pg` ones, run by ctest inside
// `with_pg_server`), a fresh database on that PostgreSQL server. The same test source runs on
// both backends: `location()` is all a test knows of where its data goes.

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <unistd.h>

#include "tocd/db/database.hpp"
#include "tocd/test/temp_dir.hpp"

#ifdef TOCD_DB_TEST_SERVER
#include <libpq-fe.h>
#endif

namespace tocd::db::testing {

class TestDatabase {
 public:
  TestDatabase() {
#ifdef TOCD_DB_TEST_SERVER
    static std::atomic<int> counter{0};
    name_ = "tocd_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
    admin("DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)");
    admin("CREATE DATABASE " + name_);
    location_ = "postgresql:///" + name_;
#else
    location_ = (dir_ / "lab.sqlite").string();
#endif
  }
  ~TestDatabase() {
#ifdef TOCD_DB_TEST_SERVER
    try {
      admin("DROP DATABASE IF EXISTS " + name_ + " WITH (FORCE)");
    } catch (...) {  // the server is gone: the session's cluster goes with it
    }
#endif
  }
  TestDatabase(const TestDatabase&) = delete;
  TestDatabase& operator=(const TestDatabase&) = delete;

  /// What `--db` / Database / Reader / Writer take: a file path or a postgresql:// URI.
  const std::string& location() const noexcept {
    return location_;
  }
  /// A scratch directory for the test's other files (exports, CSVs).
  const tocd::test::TempDir& dir() const noexcept {
    return dir_;
  }
  static constexpr bool server() noexcept {
#ifdef TOCD_DB_TEST_SERVER
    return true;
#else
    return false;
#endif
  }

#ifdef TOCD_DB_TEST_SERVER
  /// The test's database on the server.
  const std::string& name() const noexcept {
    return name_;
  }
  /// Runs SQL on the test's database, as another client of the server would.
  void exec(const std::string& sql) const {
    run_sql(name_, sql);
  }
  /// Runs SQL on the server's maintenance database.
  static void admin(const std::string& sql) {
    run_sql("postgres", sql);
  }
#endif

 private:
#ifdef TOCD_DB_TEST_SERVER
  /// Runs SQL on database `dbname` of the server (PGHOST, PGPORT, PGUSER, PGPASSWORD from the
  /// environment with_pg_server sets up); throws naming the SQL and the server's message.
  static void run_sql(const std::string& dbname, const std::string& sql) {
    if (!std::getenv("PGPORT"))
      throw std::runtime_error(
          "no PostgreSQL test server: run this binary through tests/db/with_pg_server "
          "(ctest does)");
    const std::string conninfo = "dbname=" + dbname;
    PGconn* c = PQconnectdb(conninfo.c_str());
    PQsetNoticeProcessor(
        c, [](void*, const char*) {}, nullptr);  // "does not exist, skipping"
    std::string error;
    if (PQstatus(c) != CONNECTION_OK) {
      error = PQerrorMessage(c);
    } else {
      PGresult* r = PQexec(c, sql.c_str());
      if (PQresultStatus(r) != PGRES_COMMAND_OK && PQresultStatus(r) != PGRES_TUPLES_OK)
        error = PQerrorMessage(c);
      PQclear(r);
    }
    PQfinish(c);
    if (!error.empty()) throw std::runtime_error(sql + ": " + error);
  }
#endif

  tocd::test::TempDir dir_{"db_test"};
  std::string name_;
  std::string location_;
};

/// A test with a fresh database of its own, open for writing from its start.
class OpenDatabaseTest : public ::testing::Test {
 protected:
  TestDatabase dir_;
  const std::string path_ = dir_.location();
  Database db_{path_};
};

/// A new run in `db` with one channel `name` in `unit`: what a test records samples into.
inline Channel run_with_channel(Database& db, const std::string& name, const std::string& unit,
                                double nominal_rate_Hz = kUnset) {
  const auto run = db.create_run({}).id;
  return db.add_channel({0, run, name, unit, 0, nominal_rate_Hz});
}

/// A prediction of step `step` of `run` as a test stores one: the config that made it and its
/// T (and standard error); timings, version and summary left unset.
inline PredictionRecord prediction_of(std::int64_t run, int step, std::string config_json, double T,
                                      double T_stderr = kUnset) {
  PredictionRecord p;
  p.run_id = run;
  p.step_index = step;
  p.config_json = std::move(config_json);
  p.T = T;
  p.T_stderr = T_stderr;
  return p;
}

}  // namespace tocd::db::testing

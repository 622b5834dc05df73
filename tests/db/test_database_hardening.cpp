// Opening database files of unknown origin: defensive SQLite settings, WAL confirmed, a
// damaged file flagged on open, and a WAL database in a read-only directory still readable.
#include <filesystem>
#include <fstream>
#include <string>

#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include "raw_sqlite.hpp"
#include "schema.hpp"
#include "sqlite_util.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/test/temp_dir.hpp"

namespace {

using ::testing::HasSubstr;
using tocd::db::Database;
using tocd::db::DatabaseError;
using tocd::db::Reader;
using tocd::test::TempDir;

void make_run(const std::filesystem::path& path, const std::string& name) {
  Database db(path);
  tocd::db::NewRun r;
  r.name = name;
  const auto run = db.create_run(r);
  db.set_run_status(run.id, tocd::db::RunStatus::completed);
}

}  // namespace

TEST(DbHardening, ConnectionsAreDefensiveWithUntrustedSchema) {
  const TempDir dir("db_hardening");
  tocd::db::detail::Connection c(dir / "any.sqlite", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  int defensive = -1;
  ASSERT_EQ(sqlite3_db_config(c.get(), SQLITE_DBCONFIG_DEFENSIVE, -1, &defensive), SQLITE_OK);
  EXPECT_EQ(defensive, 1);
  EXPECT_EQ(c.query_int("PRAGMA trusted_schema"), 0);
  // Defensive mode: the schema cannot be edited by hand, even with writable_schema.
  c.exec("CREATE TABLE t(a)");
  c.exec("PRAGMA writable_schema=ON");
  EXPECT_THROW(c.exec("UPDATE sqlite_master SET sql = 'CREATE TABLE t(b)' WHERE name = 't'"), DatabaseError);
}

TEST(DbHardening, WriterConfirmsWalAndReportsOtherModes) {
  const TempDir dir("db_hardening");
  Database db(dir / "lab.sqlite");
  EXPECT_EQ(db.journal_mode(), "wal");
  // An in-memory database cannot use WAL: the mode in force is returned, not an error.
  tocd::db::detail::Connection mem(":memory:", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  EXPECT_EQ(tocd::db::detail::configure_read_write(mem), "memory");
}

TEST(DbHardening, HealthyFileOpensWithoutWarnings) {
  const TempDir dir("db_hardening");
  make_run(dir / "lab.sqlite", "fine");
  const Reader reader(dir / "lab.sqlite");
  EXPECT_TRUE(reader.warnings().empty());
  EXPECT_EQ(reader.runs().size(), 1u);
}

TEST(DbHardening, DamagedFileIsFlaggedOnOpen) {
  const TempDir dir("db_hardening");
  const auto path = dir / "lab.sqlite";
  make_run(path, "before the damage");
  std::int64_t root = 0, page_size = 0;
  {
    // Enough events for a multi-page table, then the table's root page is overwritten.
    tocd::db::detail::Connection c(path, SQLITE_OPEN_READWRITE);
    c.exec(
        "WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 2000) "
        "INSERT INTO events(run_id, t_ns, kind, message) SELECT 1, i, 'note', printf('%0200d', i) FROM n");
    c.exec("PRAGMA wal_checkpoint(TRUNCATE)");
    root = c.query_int("SELECT rootpage FROM sqlite_master WHERE name = 'events'");
    page_size = c.query_int("PRAGMA page_size");
  }
  ASSERT_GT(root, 1);
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp((root - 1) * page_size);
    const std::string garbage(64, '\xA5');
    f.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
  }
  const Reader reader(path);  // still opens: the runs table is intact
  ASSERT_EQ(reader.warnings().size(), 1u);
  EXPECT_THAT(reader.warnings()[0], HasSubstr(path.string() + "' is damaged (SQLite quick_check)"));
  EXPECT_THAT(reader.warnings()[0], HasSubstr("; Page "));  // one problem after another, no line breaks
  EXPECT_EQ(reader.runs().size(), 1u);
}

// Opens a Reader and a Database on `path` as a user who may not write its directory: as
// root, in a child that drops to "nobody"; otherwise with the directory made read-only.
// Returns "" when both behave, else what went wrong.
std::string open_without_write_access(const std::filesystem::path& path) {
  auto check = [&]() -> std::string {
    try {
      const Reader reader(path);
      if (reader.runs().size() != 1) return "the reader did not see the run";
      if (reader.warnings().size() != 1 ||
          reader.warnings()[0].find("was opened read-only as it stands: its directory is not writable") ==
              std::string::npos)
        return "no note about the read-only open";
    } catch (const DatabaseError& e) {
      return std::string("reader: ") + e.what();
    }
    try {
      Database db(path);
      return "the database opened for writing";
    } catch (const DatabaseError& e) {
      // As "nobody" the file is read-only too; as its owner only the directory is.
      if (std::string(e.what()).find("cannot be written here (") == std::string::npos)
        return std::string("writer: ") + e.what();
    }
    return "";
  };
  if (::geteuid() != 0) {
    const auto dir = path.parent_path();
    std::filesystem::permissions(dir, std::filesystem::perms::owner_write,
                                 std::filesystem::perm_options::remove);
    const std::string result = check();
    std::filesystem::permissions(dir, std::filesystem::perms::owner_write,
                                 std::filesystem::perm_options::add);
    return result;
  }
  int pipe_fd[2];
  if (::pipe(pipe_fd) != 0) return "pipe failed";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(pipe_fd[0]);
    std::string result = (::setgid(65534) == 0 && ::setuid(65534) == 0) ? check() : "cannot drop to nobody";
    if (result.empty()) result = "ok";
    (void)!::write(pipe_fd[1], result.data(), result.size());
    ::_exit(0);
  }
  ::close(pipe_fd[1]);
  std::string result;
  char buf[512];
  for (ssize_t n; (n = ::read(pipe_fd[0], buf, sizeof buf)) > 0;)
    result.append(buf, static_cast<std::size_t>(n));
  ::close(pipe_fd[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return result == "ok" ? "" : result;
}

TEST(DbHardening, WalDatabaseInReadOnlyDirectoryOpensReadOnly) {
  const TempDir dir("db_hardening");
  const auto path = dir / "lab.sqlite";
  make_run(path, "archived");
  // tocdlab's last writer leaves a file in rollback mode; one still in WAL mode (its writer was
  // killed, or an older tocdlab wrote it) is what needs the read-only open.
  ASSERT_EQ(tocd::db::testing::raw_exec(path, "PRAGMA journal_mode=WAL"), "");
  ASSERT_FALSE(std::filesystem::exists(path.string() + "-shm"));  // removed on the last close
  std::filesystem::permissions(dir.path(), std::filesystem::perms(0755));
  std::filesystem::permissions(path, std::filesystem::perms(0644));
  EXPECT_EQ(open_without_write_access(path), "");
}

// A file at rest (its last writer closed) is in rollback mode: a read-only directory is no
// obstacle and needs no note, and nothing is written beside it.
TEST(DbHardening, ADatabaseAtRestInAReadOnlyDirectoryOpensWithoutANote) {
  const TempDir dir("db_hardening");
  const auto path = dir / "lab.sqlite";
  make_run(path, "archived");
  std::filesystem::permissions(dir.path(), std::filesystem::perms(0555));
  {
    const Reader reader(path);
    EXPECT_EQ(reader.runs().size(), 1u);
    EXPECT_TRUE(reader.warnings().empty()) << reader.warnings()[0];
  }
  EXPECT_FALSE(std::filesystem::exists(path.string() + "-wal"));
  EXPECT_FALSE(std::filesystem::exists(path.string() + "-shm"));
  std::filesystem::permissions(dir.path(), std::filesystem::perms(0755));
}

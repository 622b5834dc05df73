#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "tocd/core/error.hpp"
#include "tocd/db/records.hpp"

namespace tocd::db {

/// A database file that cannot be opened, is not a tocdlab database, comes from a newer
/// schema, or a request the stored data cannot satisfy (unknown run, wrong run state).
using DatabaseError = ErrorOf<struct DatabaseModule, Error>;

/// Where an interrupted run continues (Database::resume_run).
struct ResumePoint {
  RunRecord run;                   // status is `running` again
  int first_incomplete_step = 0;   // lowest step index without a completed step row
  std::int64_t gap_from_t_ns = 0;  // last recorded time of the run (sample, event or step)
  std::int64_t gap_to_t_ns = 0;    // the run's clock at the resume: now (monotonic), or just
                                   // after gap_from_t_ns when that is later; the new segment's
                                   // clock starts here
  EventRecord gap_event;           // the "gap" event recorded in the run
};

/// One tocdlab measurement database: an SQLite file (WAL mode), or, when the location is a
/// PostgreSQL connection URI (location.hpp), a server database, with the same contracts
/// (docs/database.md, "PostgreSQL": the schema is created in an empty server database; the run
/// lock is a session advisory lock there).
///
/// Opening applies schema migrations and marks runs left `running` by a process that is gone
/// (crash, kill -9, power loss) as `interrupted`. A run that is recording in another live
/// process is recognised by an advisory lock (file "<db>-runlock") and left alone.
/// A file that is not a tocdlab database, or one written by a newer schema, is refused with
/// a DatabaseError and not modified.
///
/// Thread-safe: every method may be called from any thread (one internal connection behind a
/// mutex). Each call is its own transaction, committed before it returns. Bulk time series
/// go through a Writer (writer.hpp), not through this class.
class Database {
 public:
  static constexpr int kSchemaVersion = 4;
  static constexpr std::int32_t kApplicationId = 0x544F4344;  // "TOCD" (PRAGMA application_id)

  /// Opens (creating when absent) the database at `path`, a file or a postgresql:// URI; see
  /// the class comment. A server that cannot be reached is a DatabaseError naming it.
  static Database open(const std::filesystem::path& path);
  explicit Database(const std::filesystem::path& path);
  ~Database();
  Database(Database&&) noexcept;
  Database& operator=(Database&&) noexcept;
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  const std::filesystem::path& path() const noexcept;
  /// The schema version stored in the file (PRAGMA user_version).
  int schema_version() const;
  /// Ids of the runs this open marked `interrupted`.
  const std::vector<std::int64_t>& interrupted_on_open() const noexcept;
  /// The journal mode in force: "wal", unless SQLite could not switch the file to WAL
  /// (then a warning was logged on open).
  const std::string& journal_mode() const noexcept;
  /// PRAGMA integrity_check: "ok" or the problems found.
  std::string integrity_check() const;

  // Catalogue
  std::int64_t add_instrument(const InstrumentRecord& instrument);  // upsert by (model, serial)
  std::int64_t add_sample(const SampleRecord& sample);

  // Run lifecycle
  /// Creates a run in state `running`, anchored now, with segment 0 anchor; holds its lock.
  RunRecord create_run(const NewRun& run);
  /// Leaves `running` (completed / aborted / interrupted): sets ended_utc_ns, releases the
  /// lock. Setting `running` is refused: use resume_run.
  void set_run_status(std::int64_t run_id, RunStatus status);
  void set_baseline_power(std::int64_t run_id, double baseline_power_W);
  /// Moves the end of a run that has left `running` to now (its predictions landed after its
  /// recording ended); a running run is left alone.
  void mark_run_ended(std::int64_t run_id);
  /// Continues an `interrupted` or `aborted` run in the same run: status back to `running`,
  /// a new anchor segment, a "gap" event from the last recorded time to now. Refuses a
  /// completed run or one that is running. `clock_factor`: the resumed segment's clock rate
  /// (NewRun::clock_factor).
  ResumePoint resume_run(std::int64_t run_id, double clock_factor = 1.0);
  /// True while some process (this one included) holds the run's recording lock.
  bool is_live(std::int64_t run_id) const;

  /// Adds a channel to a run; returns it with its id. Names are unique within a run.
  Channel add_channel(const Channel& channel);
  /// Adds or replaces the step (run_id, index) with its channel statistics; returns its id.
  std::int64_t add_step(const StepRecord& step);
  std::int64_t add_event(const EventRecord& event);
  std::int64_t add_prediction(const PredictionRecord& prediction);

  /// Lowest step index of the run without a completed step row.
  int first_incomplete_step(std::int64_t run_id) const;
  RunRecord run(std::int64_t run_id) const;  // DatabaseError when absent

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tocd::db

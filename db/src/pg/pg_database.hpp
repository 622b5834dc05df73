#pragma once

// Database (database.hpp) on a PostgreSQL server: the same lifecycle and contracts as on an
// SQLite file. The run lock is a session-level advisory lock (kLockSpace, run id): the server
// drops it when the recording process's connection ends, however it ends, as the kernel
// drops the file lock.

#include <cstdint>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "pg_util.hpp"
#include "tocd/db/database.hpp"

namespace tocd::db::pg {

class PgDatabase {
 public:
  /// Connects, creates the schema in an empty database, marks runs left running by a session
  /// that is gone as interrupted.
  explicit PgDatabase(const std::string& uri);

  const std::vector<std::int64_t>& interrupted_on_open() const noexcept { return interrupted_; }
  int schema_version() const;
  /// "ok", or what is inconsistent: the server checks its own pages, so this checks what the
  /// schema leaves to the writer (samples have no foreign keys: see pg_schema.cpp).
  std::string integrity_check() const;

  std::int64_t add_instrument(const InstrumentRecord& in);
  std::int64_t add_sample(const SampleRecord& sp);
  RunRecord create_run(const NewRun& in, const RunRecord& prepared);
  void set_run_status(std::int64_t run_id, RunStatus status);
  void set_baseline_power(std::int64_t run_id, double baseline_power_W);
  void mark_run_ended(std::int64_t run_id);
  ResumePoint resume_run(std::int64_t run_id, double clock_factor);
  bool is_live(std::int64_t run_id) const;
  Channel add_channel(const Channel& ch);
  std::int64_t add_step(const StepRecord& st);
  std::int64_t add_event(const EventRecord& e);
  std::int64_t add_prediction(const PredictionRecord& p);
  int first_incomplete_step(std::int64_t run_id) const;
  RunRecord run(std::int64_t run_id) const;

 private:
  std::int64_t insert_event(const EventRecord& e);
  void add_anchor(std::int64_t run_id, std::int64_t wall, std::int64_t mono, double clock_factor);
  bool acquire(std::int64_t run_id);
  void release(std::int64_t run_id);
  bool held(std::int64_t run_id) const;
  void mark_interrupted();

  Connection c_;
  std::set<std::int64_t> held_;  // run locks this session holds
  std::vector<std::int64_t> interrupted_;
  mutable std::mutex mu_;  // guards c_ and held_: one statement or transaction at a time
};

}  // namespace tocd::db::pg

#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "tocd/db/records.hpp"

namespace tocd::db {

/// A run with a few counts, for listings.
struct RunSummary {
  RunRecord run;
  int steps = 0;  // step rows (completed or not)
  int predictions = 0;
  int events = 0;
  bool live = false;  // a process holds the run's recording lock right now
};

/// shown_status for a listing entry: `interrupted` for a run stored as running that no live
/// process records.
inline RunStatus shown_status(const RunSummary& s) {
  return s.run.status == RunStatus::running && !s.live ? RunStatus::interrupted : s.run.status;
}

enum class Decimation {
  none,     // every sample in the range
  mean,     // one point per time bucket: mean time, mean value
  min_max,  // two points per time bucket: the minimum and the maximum (keeps spikes visible)
};

struct SampleQuery {
  std::int64_t from_t_ns = std::numeric_limits<std::int64_t>::min();  // inclusive
  std::int64_t to_t_ns = std::numeric_limits<std::int64_t>::max();    // inclusive
  /// With mean/min_max: at most about this many points are returned (buckets of equal time
  /// width over the samples' actual time span). Ignored with none.
  std::size_t max_points = 2000;
  Decimation decimation = Decimation::none;
};

/// A step next to its latest prediction (the compare table).
struct CompareRow {
  StepRecord step;
  std::optional<PredictionRecord> prediction;
  double relative_difference = kUnset;  // (predicted T - measured T) / measured T
};

/// Read-only access to a tocdlab database, safe while a run records into it: every query
/// reads a consistent snapshot of what is committed (WAL), never takes the write lock and so
/// never blocks the Writer; a busy timeout covers the rare moments SQLite needs a lock
/// (WAL recovery after a crash).
///
/// Thread-safe (one connection behind a mutex). The file must exist and be a tocdlab
/// database of the current schema; otherwise DatabaseError (the file is not modified). The
/// connection runs in SQLite's defensive mode with trusted_schema off.
///
/// `db_path` may be a PostgreSQL connection URI (location.hpp): a read-only session on the
/// server; queries that describe one instant read one REPEATABLE READ snapshot.
class Reader {
 public:
  explicit Reader(const std::filesystem::path& db_path);
  ~Reader();
  Reader(Reader&&) noexcept;
  Reader& operator=(Reader&&) noexcept;
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  /// What opening found and logged (at warn): a damaged file (SQLite quick_check, run on
  /// every open), or a WAL database read as it stands from a directory that is not writable.
  /// Empty for a healthy file.
  const std::vector<std::string>& warnings() const noexcept;

  std::vector<RunSummary> runs() const;  // ordered by id
  std::optional<RunRecord> find_run(std::int64_t run_id) const;
  RunRecord run(std::int64_t run_id) const;  // DatabaseError when absent
  std::vector<RunAnchor> anchors(std::int64_t run_id) const;
  bool is_live(std::int64_t run_id) const;
  /// The status to show for a run: one stored as `running` whose recording lock nobody holds
  /// was left by a dead process (kill -9, power loss) and is shown as `interrupted`, which is
  /// what the next writer to open the file stores (a reader never writes). run() and runs()
  /// return the stored status.
  RunStatus shown_status(std::int64_t run_id) const;

  std::optional<InstrumentRecord> instrument(std::int64_t instrument_id) const;
  std::vector<InstrumentRecord> instruments() const;
  std::optional<SampleRecord> sample(std::int64_t sample_id) const;

  std::vector<Channel> channels(std::int64_t run_id) const;  // ordered by id
  /// The channel of a run with this name, if any.
  std::optional<Channel> channel(std::int64_t run_id, const std::string& name) const;
  /// Samples of one channel ordered by time.
  std::vector<Sample> samples(std::int64_t channel_id, const SampleQuery& query = {}) const;
  std::int64_t sample_count(std::int64_t channel_id, const SampleQuery& query = {}) const;

  std::vector<StepRecord> steps(std::int64_t run_id) const;              // ordered by index
  std::vector<EventRecord> events(std::int64_t run_id) const;            // ordered by time
  std::vector<PredictionRecord> predictions(std::int64_t run_id) const;  // by step, then id
  std::vector<CompareRow> compare(std::int64_t run_id) const;            // one row per completed step
  int first_incomplete_step(std::int64_t run_id) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tocd::db

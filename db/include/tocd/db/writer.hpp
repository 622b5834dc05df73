#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>

#include "tocd/db/records.hpp"

namespace tocd::db {

class Database;

/// A batch the writer could not commit (after its retries): its rows are lost.
struct WriterFailure {
  std::uint64_t samples = 0;        ///< samples of this batch
  std::uint64_t events = 0;         ///< events of this batch
  std::uint64_t samples_total = 0;  ///< samples lost to failed commits so far
  std::string error;                ///< the database's message (e.g. "database or disk is full")
};

struct WriterOptions {
  /// A batch is committed at the latest this long after its first row was enqueued...
  std::chrono::milliseconds batch_interval{100};
  /// ...or as soon as this many rows wait, whichever comes first.
  std::size_t batch_rows = 50000;
  /// Rows that may wait in memory; beyond it enqueue drops the row and counts it.
  std::size_t queue_capacity = 2'000'000;
  /// Called on the writer thread, without its lock held, after each batch that could not be
  /// committed. Must return quickly; whatever it throws is logged and dropped.
  std::function<void(const WriterFailure&)> on_failure;
  /// Largest size the writer lets the file grow to, in database pages (PRAGMA max_page_count
  /// on its connection); 0 = no limit. A commit beyond it fails like a full disk.
  std::uint64_t max_page_count = 0;
};

struct WriterStats {
  std::uint64_t enqueued = 0;        // accepted by enqueue
  std::uint64_t written = 0;         // committed to the file
  std::uint64_t dropped = 0;         // refused by enqueue because the queue was full
  std::uint64_t rejected = 0;        // not storable (unknown channel or run id); see last_error
  std::uint64_t failed = 0;          // lost to a database error (disk full, ...); see last_error
  std::uint64_t failed_samples = 0;  // the samples among `failed`
  std::uint64_t batches = 0;         // committed transactions
  std::size_t queue_depth = 0;
  std::size_t queue_high_water = 0;
  double last_batch_ms = 0, mean_batch_ms = 0, max_batch_ms = 0;  // commit latency per batch
  /// Longest time from a row's enqueue to the commit of its batch: the age beyond which every
  /// enqueued row was on disk (the measured durability window of this writer).
  double max_commit_delay_ms = 0;
  double writer_cpu_seconds = 0;  // CPU time of the writer thread so far
  std::string last_error;         // "" while all is well
};

/// Background writer of time-series samples (and, optionally, events) into a tocdlab
/// database, on its own thread and its own SQLite connection.
///
/// Acquisition threads call enqueue(), which never waits on I/O: it appends to a bounded
/// in-memory queue under a short mutex (O(1)) and returns. The writer thread takes what is
/// queued and inserts it with prepared statements, one transaction per batch, committing at
/// least every `batch_interval` (default 0.1 s) or every `batch_rows` rows.
///
/// Durability (WAL mode, synchronous=NORMAL): a committed batch survives a crash or kill of
/// the process; a power loss or OS crash may lose the batches committed since the last WAL
/// checkpoint sync, never corrupts the file. So after a process kill, every sample enqueued
/// more than batch_interval + one batch's commit time earlier is in the file (docs/database.md
/// states 0.5 s as the bound the tests hold it to).
///
/// Readers (Reader, other processes) never block the writer, and vice versa (WAL). Samples
/// must name channels created with Database::add_channel before they are enqueued.
///
/// On a PostgreSQL server (a Database or path that is a postgresql:// URI) each batch is one
/// transaction with its samples sent by COPY; a commit is durable when it returns (the
/// server's synchronous_commit), and a connection lost under a batch is reset before the retry.
class Writer {
 public:
  /// Opens its own connection to an existing tocdlab database (opened once by Database so
  /// its schema is current) and starts the writer thread.
  explicit Writer(const std::filesystem::path& db_path, WriterOptions options = {});
  explicit Writer(const Database& db, WriterOptions options = {});
  /// Flushes what is queued and stops the thread.
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// Thread-safe, non-blocking. False when the queue is full (the sample is counted dropped).
  bool enqueue(const Sample& sample) noexcept;
  /// Thread-safe, non-blocking; returns how many were accepted (the rest are dropped).
  std::size_t enqueue(std::span<const Sample> samples) noexcept;
  /// Thread-safe; events share the queue and the transactions of samples.
  bool enqueue(const EventRecord& event) noexcept;

  /// Blocks until everything enqueued before the call is committed (or rejected).
  void flush();
  /// Flushes and stops the thread; enqueue afterwards drops. Idempotent.
  void stop();

  WriterStats stats() const;
  const WriterOptions& options() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tocd::db

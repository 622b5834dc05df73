#pragma once

// The recorder: where a run's readings go. It owns the database writer (samples and events,
// batched), the run's channels (one slot each, in the order the instruments describe them),
// the counts of samples stored and refused, and the recording window of the step under way,
// with the lock that guards that window.

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "tocd/core/running_stats.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/writer.hpp"

namespace tocd::acquisition {

class Recorder {
 public:
  /// Adds the run's channel `id` (stored in the database); returns its slot (0, 1, ...).
  /// Every slot is added before start().
  int add_channel(std::int64_t id);
  int slots() const { return static_cast<int>(channel_.size()); }
  std::int64_t channel(int slot) const { return channel_[static_cast<std::size_t>(slot)]; }

  /// Starts the writer thread.
  void start(db::Database& db, db::WriterOptions options);
  /// Stops the writer: everything it accepted is in the file (or counted as failed) after this.
  void stop();

  /// A reading of `slot`: to the writer, and into the recording window while one is open.
  void add(int slot, std::int64_t t_ns, double value);
  /// Queues an event in order with the samples; false when the writer does not take it (not
  /// started, stopped, or its queue is full): then the caller stores it directly.
  bool enqueue_event(const db::EventRecord& event);

  /// Opens a fresh recording window; every reading from now on counts in it.
  void open_window();
  /// Closes the window and returns what it saw, per slot.
  std::vector<RunningStats> close_window();

  std::uint64_t enqueued() const noexcept { return enqueued_; }
  std::uint64_t dropped() const noexcept { return dropped_; }
  db::WriterStats writer_stats() const;

 private:
  std::vector<std::int64_t> channel_;   // fixed once start() ran
  std::unique_ptr<db::Writer> writer_;  // set in start(), before any poller runs
  std::atomic<std::uint64_t> enqueued_{0}, dropped_{0};

  // Guards window_open_ and window_: pollers add, the sequencer opens and closes.
  std::mutex window_mu_;
  bool window_open_ = false;
  std::vector<RunningStats> window_;
};

}  // namespace tocd::acquisition

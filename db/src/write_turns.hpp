#pragma once

// Turns at one database file's write lock among the connections of this process. SQLite's
// lock is not fair: a connection that commits a backlog batch after batch takes the lock
// again microseconds after each commit, while another connection's busy handler sleeps up to
// 100 ms between tries and can miss every gap until its busy timeout runs out. The recorder's
// background writer does exactly that when it catches up, and the run's own writes (a step,
// an event, the run's status) are the other connection. So a connection about to take the
// lock says so here, and the background writer lets such a connection go first.

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>

namespace tocd::db::detail {

class WriteTurns {
 public:
  /// The turns of `file` in this process, shared by every read-write connection to it.
  static std::shared_ptr<WriteTurns> of(const std::filesystem::path& file);

  /// While it lives, this thread is waiting for the file's write lock.
  class Waiting {
   public:
    explicit Waiting(WriteTurns* turns);
    ~Waiting();
    Waiting(const Waiting&) = delete;
    Waiting& operator=(const Waiting&) = delete;

   private:
    WriteTurns* turns_;
  };

  /// Returns once no other connection of this process waits for the write lock, or after
  /// `limit` (a waiter gives up at its busy timeout anyway).
  void let_waiting_writers_first(std::chrono::milliseconds limit);

 private:
  std::mutex mu_;
  std::condition_variable none_waiting_;
  int waiting_ = 0;
};

}  // namespace tocd::db::detail

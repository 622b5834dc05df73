#pragma once

// Commands the sequencer queues for the poller that owns an instrument's driver, and what
// became of each: the sequencer learns whether its move (or stop, or limit write) was carried
// out or what the instrument answered instead.

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>

namespace tocd::acquisition {

class CommandQueue {
 public:
  using Failure = std::function<void(const std::string& what, const std::string& error)>;

  /// Queues `fn` (described by `what` in events); returns its number (1, 2, ... in order).
  std::uint64_t push(std::string what, std::function<void()> fn);

  /// Runs every queued command on the calling thread (the driver's owner), in order. A command
  /// that throws is recorded as failed with the exception's message and reported to
  /// `on_failure`. Returns the number of the last command run so far.
  std::uint64_t drain(const Failure& on_failure);

  /// Number of the last command pushed.
  std::uint64_t last_pushed() const;
  /// Number of the last command run (succeeded or failed).
  std::uint64_t last_run() const;

  /// Outcome of command `id`: nothing while it has not run, "" when it succeeded, otherwise
  /// what went wrong (the driver's error, i.e. the instrument's answer).
  std::optional<std::string> outcome(std::uint64_t id) const;

 private:
  struct Entry {
    std::uint64_t id;
    std::string what;
    std::function<void()> fn;
  };
  // Failures older than this many commands are forgotten (nobody waits on them any more).
  static constexpr std::uint64_t kKeptFailures = 1000;

  mutable std::mutex mu_;
  std::deque<Entry> queue_;
  std::uint64_t pushed_ = 0;
  std::uint64_t run_ = 0;
  std::map<std::uint64_t, std::string> failures_;
};

}  // namespace tocd::acquisition

#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace tocd::devices {

/// Bounds one whole Modbus TCP transaction. libmodbus times the first byte of an answer and
/// then each further byte on its own, so an instrument that trickles one byte just inside the
/// byte timeout stretches a request without limit (one byte every 90 ms: a 0.5 s request for
/// 107 bytes takes 9.6 s and succeeds).
/// While armed, a watcher thread shuts the socket down when the deadline passes; the blocked
/// libmodbus call then fails at once, and the caller reports a timeout and reconnects.
class AnswerDeadline {
 public:
  AnswerDeadline() = default;
  ~AnswerDeadline();
  AnswerDeadline(const AnswerDeadline&) = delete;
  AnswerDeadline& operator=(const AnswerDeadline&) = delete;

  /// Watches socket `fd` until disarm() or `deadline`, whichever comes first.
  void arm(int fd, std::chrono::steady_clock::time_point deadline);
  /// Stops watching; true when the deadline passed and the socket was shut down. After it
  /// returns, the socket is never touched again (the fd number may be reused).
  bool disarm();

 private:
  void watch();

  std::mutex mutex_;
  std::condition_variable wake_;
  int fd_ = -1;
  std::chrono::steady_clock::time_point deadline_{};
  bool armed_ = false;
  bool fired_ = false;
  bool stop_ = false;
  std::thread thread_;  // started on the first arm(), so links that never use it cost nothing
};

}  // namespace tocd::devices

#include "modbus/answer_deadline.hpp"

#include <sys/socket.h>

namespace tocd::devices {

AnswerDeadline::~AnswerDeadline() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void AnswerDeadline::arm(int fd, std::chrono::steady_clock::time_point deadline) {
  {
    std::lock_guard lock(mutex_);
    fd_ = fd;
    deadline_ = deadline;
    armed_ = true;
    fired_ = false;
    if (!thread_.joinable()) thread_ = std::thread([this] { watch(); });
  }
  wake_.notify_all();
}

bool AnswerDeadline::disarm() {
  std::lock_guard lock(mutex_);
  armed_ = false;
  fd_ = -1;
  return fired_;
}

void AnswerDeadline::watch() {
  std::unique_lock lock(mutex_);
  while (!stop_) {
    if (!armed_) {
      wake_.wait(lock);
      continue;
    }
    const auto deadline = deadline_;
    wake_.wait_until(lock, deadline);
    // Shut down under the lock: disarm() cannot return in between, so the fd is still ours.
    if (armed_ && deadline_ == deadline && std::chrono::steady_clock::now() >= deadline) {
      ::shutdown(fd_, SHUT_RDWR);
      fired_ = true;
      armed_ = false;
    }
  }
}

}  // namespace tocd::devices

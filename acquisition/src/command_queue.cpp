#include "command_queue.hpp"

#include <exception>

namespace tocd::acquisition {

std::uint64_t CommandQueue::push(std::string what, std::function<void()> fn) {
  std::lock_guard lock(mu_);
  queue_.push_back({++pushed_, std::move(what), std::move(fn)});
  return pushed_;
}

std::uint64_t CommandQueue::drain(const Failure& on_failure) {
  for (;;) {
    Entry e;
    {
      std::lock_guard lock(mu_);
      if (queue_.empty()) return run_;
      e = std::move(queue_.front());
      queue_.pop_front();
    }
    std::string error;
    try {
      e.fn();
    } catch (const std::exception& ex) {
      error = ex.what();
      if (error.empty()) error = "failed without a message";
    } catch (...) {
      error = "failed with an unknown error";
    }
    {
      std::lock_guard lock(mu_);
      run_ = e.id;
      if (!error.empty()) failures_[e.id] = error;
      while (!failures_.empty() && failures_.begin()->first + kKeptFailures < run_) {
        failures_.erase(failures_.begin());
      }
    }
    if (!error.empty() && on_failure) on_failure(e.what, error);
  }
}

std::uint64_t CommandQueue::last_pushed() const {
  std::lock_guard lock(mu_);
  return pushed_;
}

std::uint64_t CommandQueue::last_run() const {
  std::lock_guard lock(mu_);
  return run_;
}

std::optional<std::string> CommandQueue::outcome(std::uint64_t id) const {
  std::lock_guard lock(mu_);
  if (id > run_) return std::nullopt;
  const auto it = failures_.find(id);
  return it == failures_.end() ? std::string() : it->second;
}

}  // namespace tocd::acquisition

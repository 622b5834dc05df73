// The team of one process. Messages a process sends to itself are queued and received in
// order, so the study's dispatcher protocol runs unchanged without MPI.
#include <condition_variable>
#include <deque>
#include <mutex>
#include <stdexcept>

#include "tocd/sim/parallel/team.hpp"

namespace tocd::sim::parallel {
namespace {

class SoloTeam final : public Team {
 public:
  int rank() const noexcept override { return 0; }
  int size() const noexcept override { return 1; }
  void sum(std::span<std::int64_t>) override {}
  void broadcast(std::vector<std::int64_t>&, int root) override {
    if (root != 0) throw std::invalid_argument("broadcast root outside a team of one");
  }
  void send(int to, int tag, std::span<const std::int64_t> words) override {
    if (to != 0) throw std::invalid_argument("send to a member outside a team of one");
    {
      std::lock_guard lock(mutex_);
      queue_.push_back({0, tag, {words.begin(), words.end()}});
    }
    arrived_.notify_all();
  }
  Message receive(int, int tag) override {
    std::unique_lock lock(mutex_);
    for (;;) {
      for (auto it = queue_.begin(); it != queue_.end(); ++it) {
        if (tag < 0 || it->tag == tag) {
          Message m = std::move(*it);
          queue_.erase(it);
          return m;
        }
      }
      arrived_.wait(lock);
    }
  }
  void abort(int) noexcept override {}

 private:
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::deque<Message> queue_;
};

}  // namespace

Team& solo() {
  static SoloTeam team;
  return team;
}

}  // namespace tocd::sim::parallel

#include "write_turns.hpp"

#include <map>
#include <string>
#include <system_error>

namespace tocd::db::detail {

std::shared_ptr<WriteTurns> WriteTurns::of(const std::filesystem::path& file) {
  static std::mutex registry_mu;
  static std::map<std::string, std::weak_ptr<WriteTurns>> registry;
  // One key for every spelling of the path (relative, through a link); the file itself may not
  // exist yet when the connection that creates it opens.
  std::error_code ec;
  auto key = std::filesystem::weakly_canonical(std::filesystem::absolute(file, ec), ec).string();
  if (ec) key = file.string();
  const std::lock_guard lk(registry_mu);
  for (auto it = registry.begin(); it != registry.end();)  // forget the files no longer open
    it = it->second.expired() ? registry.erase(it) : std::next(it);
  auto& slot = registry[key];
  auto turns = slot.lock();
  if (!turns) {
    turns = std::make_shared<WriteTurns>();
    slot = turns;
  }
  return turns;
}

WriteTurns::Waiting::Waiting(WriteTurns* turns) : turns_(turns) {
  if (!turns_) return;
  const std::lock_guard lk(turns_->mu_);
  ++turns_->waiting_;
}

WriteTurns::Waiting::~Waiting() {
  if (!turns_) return;
  {
    const std::lock_guard lk(turns_->mu_);
    --turns_->waiting_;
  }
  turns_->none_waiting_.notify_all();
}

void WriteTurns::let_waiting_writers_first(std::chrono::milliseconds limit) {
  std::unique_lock lk(mu_);
  none_waiting_.wait_for(lk, limit, [this] { return waiting_ == 0; });
}

}  // namespace tocd::db::detail

#include "modbus_server/fault_queue.hpp"

#include "tocd/core/error.hpp"

namespace tocd::mocks {

void FaultQueue::push(const ModbusFault& f) {
  if (f.count < 1 || f.delay_s < 0.0 || f.delay_s > 60.0)
    throw ConfigError("an injected fault needs count >= 1 and delay_s in [0, 60] s");
  std::lock_guard lock(mutex_);
  faults_.push_back(f);
}

std::optional<ModbusFault> FaultQueue::take() {
  std::lock_guard lock(mutex_);
  if (faults_.empty()) return std::nullopt;
  ModbusFault f = faults_.front();
  if (--faults_.front().count == 0) faults_.pop_front();
  return f;
}

int FaultQueue::pending() const {
  std::lock_guard lock(mutex_);
  int n = 0;
  for (const auto& f : faults_) n += f.count;
  return n;
}

}  // namespace tocd::mocks

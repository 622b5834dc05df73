#pragma once

#include <deque>
#include <mutex>
#include <optional>

#include "tocd/mocks/modbus_faults.hpp"

namespace tocd::mocks {

/// Injected faults waiting for requests; each fault applies to its next `count` requests.
class FaultQueue {
 public:
  void push(const ModbusFault& f);
  std::optional<ModbusFault> take();  ///< the fault for the request being served, if any
  int pending() const;

 private:
  mutable std::mutex mutex_;
  std::deque<ModbusFault> faults_;
};

}  // namespace tocd::mocks

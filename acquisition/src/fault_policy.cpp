#include "fault_policy.hpp"

#include <fmt/format.h>

namespace tocd::acquisition {

void FaultPolicy::trip(const std::string& reason) {
  if (control_.trip(reason)) events_.emit("interlock", reason);
}

void FaultPolicy::pause(const std::string& reason) {
  if (control_.pause_for_fault(reason)) events_.emit("interlock", reason);
}

void FaultPolicy::command_failed(const std::string& instrument, const std::string& what,
                                 const std::string& error) {
  count();
  events_.emit("fault", fmt::format("{}: command '{}' failed: {}", instrument, what, error));
}

}  // namespace tocd::acquisition

#pragma once
// GoogleTest prints an instrument Identity that differs from the expected one field by field
// (found by argument-dependent lookup; without it the failure shows raw bytes).
#include <ostream>

#include "tocd/devices/instruments.hpp"

namespace tocd::devices {

inline void PrintTo(const Identity& id, std::ostream* os) {
  *os << "{vendor \"" << id.vendor << "\", model \"" << id.model << "\", serial \"" << id.serial
      << "\", firmware \"" << id.firmware << "\"}";
}

}  // namespace tocd::devices

#pragma once

// The engine reads each instrument kind through its interface (a tester's position and load,
// a meter's power, a controller's pressure): a driver whose capability table names other
// channels, or names them in another order, cannot be recorded, and says so before any run.

#include <initializer_list>
#include <string_view>

#include "tocd/devices/capabilities.hpp"

namespace tocd::acquisition {

/// Throws EngineError unless `capabilities` lists exactly the channels `expected`, in order.
void require_channels(const devices::InstrumentCapabilities& capabilities,
                      std::initializer_list<std::string_view> expected);

}  // namespace tocd::acquisition

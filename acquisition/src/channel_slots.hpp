#pragma once

// The channels a run records, as slots of per-channel arrays.

#include <array>
#include <string_view>

namespace tocd::acquisition {

enum Slot : int { kDisplacement = 0, kLoad = 1, kPower = 2, kPressure = 3, kSlots = 4 };
inline constexpr std::array<std::string_view, kSlots> kChannelNames{"displacement", "load", "power",
                                                                    "pressure"};
inline constexpr std::array<std::string_view, kSlots> kChannelUnits{"mm", "N", "W", "kPa"};

}  // namespace tocd::acquisition

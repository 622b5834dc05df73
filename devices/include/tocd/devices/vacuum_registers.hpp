#pragma once

#include <array>
#include <cstdint>

#include "tocd/devices/capabilities.hpp"

// The tocdlab vacuum pump controller register map, version 1
// (docs/instruments/vacuum-controller.md). Floats high word first (register_codec.hpp).
namespace tocd::devices::vacuum_map {

inline constexpr std::uint16_t map_version = 1;

// Input registers (function 0x04). 0..5 are read in one transaction per poll.
inline constexpr int in_pressure = 0;  ///< float, kPa absolute
inline constexpr int in_setpoint = 2;  ///< float, kPa absolute (echo of the holding register)
inline constexpr int in_status = 4;
inline constexpr int in_error_code = 5;
inline constexpr int in_poll_count = 6;
inline constexpr int in_map_version = 99;
inline constexpr int in_identity = 100;  ///< same 48-register layout as the tester
inline constexpr int input_count = 148;

inline constexpr std::uint16_t st_pump_running = 1u << 0;
inline constexpr std::uint16_t st_vent_open = 1u << 1;
inline constexpr std::uint16_t st_at_setpoint = 1u << 2;
inline constexpr std::uint16_t st_error = 1u << 3;

inline constexpr std::uint16_t err_none = 0;
inline constexpr std::uint16_t err_setpoint_not_reached = 1;  ///< seal loss or large leak
inline constexpr std::uint16_t err_pump_overload = 2;

// Holding registers.
inline constexpr int hr_setpoint = 0;     ///< float, kPa absolute, 0 < x <= atmosphere
inline constexpr int hr_pump_run = 2;     ///< 0 stop, 1 run
inline constexpr int hr_vent = 3;         ///< 0 closed, 1 open
inline constexpr int hr_clear_error = 4;  ///< write 1 to clear the error code
inline constexpr int holding_count = 5;

// The channel a run records of the controller: the chamber's absolute pressure, from the
// pump's ultimate vacuum to a little above atmosphere (setpoints are accepted up to 110 kPa).
inline constexpr std::array<ChannelCapability, 1> channels{{
    {"pressure", "kPa", 0.0, 110.0, 10.0},
}};
inline constexpr InstrumentCapabilities capabilities{"vacuum", "vacuum controller", channels};

}  // namespace tocd::devices::vacuum_map

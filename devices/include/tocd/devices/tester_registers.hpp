#pragma once

#include <array>
#include <cstdint>

#include "tocd/devices/capabilities.hpp"

// The tocdlab mechanical tester register map, version 1 (docs/instruments/mechanical-tester.md).
// Floats: IEEE-754 single over two registers, high word first (register_codec.hpp).
namespace tocd::devices::tester_map {

inline constexpr std::uint16_t map_version = 1;

// Input registers (function 0x04, read-only). 0..5 are read in one transaction per poll.
inline constexpr int in_position = 0;  ///< float, mm, 0 = home, positive = pin down
inline constexpr int in_load = 2;      ///< float, N, compressive positive, after tare
inline constexpr int in_status = 4;    ///< status bits below
inline constexpr int in_fault_code = 5;
inline constexpr int in_poll_count = 6;  ///< registers 0..5: the polling block
inline constexpr int in_map_version = 99;
inline constexpr int in_identity = 100;  ///< vendor, model, serial, firmware: ASCII, 2 chars/register
inline constexpr int identity_vendor_regs = 16;
inline constexpr int identity_model_regs = 16;
inline constexpr int identity_serial_regs = 8;
inline constexpr int identity_firmware_regs = 8;
inline constexpr int identity_regs = 48;
inline constexpr int input_count = 148;

// Status bits (input register 4).
inline constexpr std::uint16_t st_ready = 1u << 0;
inline constexpr std::uint16_t st_moving = 1u << 1;
inline constexpr std::uint16_t st_at_target = 1u << 2;
inline constexpr std::uint16_t st_limit = 1u << 3;  ///< travel or load limit tripped
inline constexpr std::uint16_t st_fault = 1u << 4;
inline constexpr std::uint16_t st_homed = 1u << 5;

// Fault codes (input register 5).
inline constexpr std::uint16_t fault_none = 0;
inline constexpr std::uint16_t fault_load_limit = 1;
inline constexpr std::uint16_t fault_travel_limit = 2;
inline constexpr std::uint16_t fault_drive = 3;

// Holding registers (functions 0x03, 0x06, 0x10).
inline constexpr int hr_target = 0;       ///< float, mm
inline constexpr int hr_velocity = 2;     ///< float, mm/s, > 0
inline constexpr int hr_command = 4;      ///< command codes below; reads back 0 once accepted
inline constexpr int hr_max_travel = 10;  ///< float, mm
inline constexpr int hr_max_load = 12;    ///< float, N
inline constexpr int holding_count = 14;

// Commands (holding register 4). move = write 0..4 in one 0x10 request.
inline constexpr std::uint16_t cmd_none = 0;
inline constexpr std::uint16_t cmd_move = 1;
inline constexpr std::uint16_t cmd_stop = 2;
inline constexpr std::uint16_t cmd_home = 3;
inline constexpr std::uint16_t cmd_tare = 4;
inline constexpr std::uint16_t cmd_clear_fault = 5;

// The channels a run records of the tester. Displacement is the position register less the
// protocol's contact position (the engine subtracts it); the ranges are the stroke and the load
// cell of the instrument this map documents (100 mm, 500 N either way).
inline constexpr std::array<ChannelCapability, 2> channels{{
    {"displacement", "mm", 0.0, 100.0, 1000.0},
    {"load", "N", -500.0, 500.0, 1000.0},
}};
inline constexpr InstrumentCapabilities capabilities{"mechanical_tester", "mechanical tester", channels};

}  // namespace tocd::devices::tester_map

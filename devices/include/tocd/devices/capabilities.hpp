#pragma once

// What an instrument gives a run, as data: each driver describes the channels it reads (name,
// unit, range, rate) in one table beside its register map or command set. The run engine makes
// its channels from it, the database's channel rows are written from it and the window's
// instrument panels are laid out from it, so a new instrument kind is its driver and its table.

#include <span>
#include <string_view>

namespace tocd::devices {

/// One channel an instrument reads: a run records it under `name`.
struct ChannelCapability {
  std::string_view name;  ///< the run's channel: "displacement", "load", "power", "pressure"
  std::string_view unit;  ///< "mm", "N", "W", "kPa"
  double min = 0;         ///< the range the instrument reads, in `unit`
  double max = 0;
  double default_rate_Hz = 0;  ///< how often a protocol reads it unless it says otherwise
};

/// One instrument kind and its channels.
struct InstrumentCapabilities {
  std::string_view kind;   ///< "mechanical_tester": the database's instrument kind
  std::string_view title;  ///< "mechanical tester": how events and panels name it
  std::span<const ChannelCapability> channels;
};

}  // namespace tocd::devices

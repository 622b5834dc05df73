#pragma once

// The instrument kinds a lab may have, in panel order, each with its driver's capability table
// (tocd/devices/capabilities.hpp): the instrument panels take their titles, and the run's live
// readings their panel and unit, from these tables.

#include <QString>
#include <array>
#include <optional>
#include <string_view>

#include "tocd/devices/capabilities.hpp"

namespace tocd::gui {

enum class InstrumentKind { tester, power_meter, vacuum };
inline constexpr std::array<InstrumentKind, 3> kInstrumentKinds{
    InstrumentKind::tester, InstrumentKind::power_meter, InstrumentKind::vacuum};

const devices::InstrumentCapabilities& capabilities_of(InstrumentKind kind);
/// "Mechanical tester": the driver's title, capitalised, for a panel.
QString panel_title(InstrumentKind kind);

/// The unit of channel `name` of `kind`'s driver ("" when it describes no such channel).
QString unit_of(InstrumentKind kind, std::string_view name);

/// The instrument kind whose driver reads the run channel `name`, and that channel.
struct ChannelOwner {
  InstrumentKind kind;
  const devices::ChannelCapability* channel;
};
std::optional<ChannelOwner> channel_owner(std::string_view name);

}  // namespace tocd::gui

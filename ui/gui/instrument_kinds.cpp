#include "instrument_kinds.hpp"

#include "tocd/devices/power_meter_drivers.hpp"
#include "tocd/devices/tester_registers.hpp"
#include "tocd/devices/vacuum_registers.hpp"

namespace tocd::gui {

const devices::InstrumentCapabilities& capabilities_of(InstrumentKind kind) {
  switch (kind) {
    case InstrumentKind::tester:
      return devices::tester_map::capabilities;
    case InstrumentKind::power_meter:
      return devices::scpi_power_meter_capabilities;
    case InstrumentKind::vacuum:
      return devices::vacuum_map::capabilities;
  }
  return devices::tester_map::capabilities;
}

QString panel_title(InstrumentKind kind) {
  QString title = QString::fromUtf8(capabilities_of(kind).title.data(),
                                    static_cast<qsizetype>(capabilities_of(kind).title.size()));
  if (!title.isEmpty()) title[0] = title[0].toUpper();
  return title;
}

QString unit_of(InstrumentKind kind, std::string_view name) {
  for (const auto& c : capabilities_of(kind).channels) {
    if (c.name == name) return QString::fromUtf8(c.unit.data(), static_cast<qsizetype>(c.unit.size()));
  }
  return {};
}

std::optional<ChannelOwner> channel_owner(std::string_view name) {
  for (const InstrumentKind kind : kInstrumentKinds) {
    for (const auto& c : capabilities_of(kind).channels) {
      if (c.name == name) return ChannelOwner{kind, &c};
    }
  }
  return std::nullopt;
}

}  // namespace tocd::gui

#pragma once

// The instruments of an engine, each an owned channel (drivers, latest readings, commands,
// interlocks), made once from the InstrumentSet it was given.

#include <memory>
#include <vector>

#include "power_channel.hpp"
#include "tester_channel.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/acquisition/protocol.hpp"
#include "vacuum_channel.hpp"

namespace tocd::acquisition {

struct InstrumentChannels {
  explicit InstrumentChannels(InstrumentSet set);

  std::unique_ptr<TesterChannel> tester;
  std::unique_ptr<PowerChannel> power;
  std::unique_ptr<VacuumChannel> vacuum;

  /// Sets what the run asks of each instrument: poll rates, whether the protocol uses it, the
  /// interlock limits, the settle windows' length and the baseline. Before the pollers start.
  void configure(const Protocol& protocol, double baseline_W);

  /// Those present, in the order their channels are recorded: tester, power meter, vacuum.
  std::vector<InstrumentChannel*> present() const;
};

}  // namespace tocd::acquisition

#pragma once

// What happens before a run's threads start: checking the lab against the protocol, the
// baseline, the tare, the tester's own limits, the instruments and channels stored with the run
// (built from each driver's capability table), and a resumed run's channels found again.

#include <cstdint>
#include <string>
#include <vector>

#include "instrument_channels.hpp"
#include "scaled_clock.hpp"
#include "tocd/acquisition/engine.hpp"

namespace tocd::acquisition {

/// Throws EngineError when an instrument the protocol needs is missing.
void check_instruments(const Protocol& protocol, const InstrumentChannels& instruments);

/// Averages the power meter for the protocol's baseline time, before any run exists.
double measure_baseline(devices::PowerMeter& meter, const Protocol& protocol, const ScaledClock& clock);

/// Zeroes the load cell before a pin run when the pin is clear of the sample; the note for the
/// run's event log ("" when there is nothing to say).
std::string tare_load_cell(const Protocol& protocol, TesterChannel* tester);

/// Writes the protocol's load limit and travel limit into the tester's own limit registers.
/// Throws EngineError when the tester does not take them.
void write_tester_limits(const Protocol& protocol, devices::MechanicalTester& tester);

/// Stores who each present instrument says it is; their ids, in InstrumentChannels::present() order.
std::vector<std::int64_t> register_instruments(db::Database& db, const InstrumentChannels& instruments);

/// Creates the run with its sample, texts, baseline and meter settings.
db::RunRecord create_run(db::Database& db, const Protocol& protocol, const EngineOptions& options,
                         double baseline_W, devices::PowerMeter& meter);

/// The run's channel rows, one per channel each present instrument describes (name and unit
/// from its capability table, its poll rate, its instrument); their ids in that order.
std::vector<std::int64_t> add_channel_rows(db::Database& db, std::int64_t run_id,
                                           const InstrumentChannels& instruments,
                                           const std::vector<std::int64_t>& instrument_ids);

/// A resumed run's channel rows, found by name (made, without instrument, where the run had
/// none); their ids in the same order.
std::vector<std::int64_t> find_channel_rows(db::Database& db, std::int64_t run_id,
                                            const InstrumentChannels& instruments);

}  // namespace tocd::acquisition

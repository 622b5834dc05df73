#pragma once

// Queries shared by Database (read-write) and Reader (read-only): one place maps rows to records.

#include <cstdint>
#include <optional>
#include <vector>

#include "record_rows.hpp"
#include "sqlite_util.hpp"
#include "tocd/db/records.hpp"

namespace tocd::db::detail {

std::optional<RunRecord> find_run(const Connection& c, std::int64_t run_id);
std::vector<RunRecord> all_runs(const Connection& c);
std::vector<RunAnchor> run_anchors(const Connection& c, std::int64_t run_id);
std::vector<Channel> run_channels(const Connection& c, std::int64_t run_id);
std::vector<StepRecord> run_steps(const Connection& c, std::int64_t run_id);
std::vector<EventRecord> run_events(const Connection& c, std::int64_t run_id);
std::vector<PredictionRecord> run_predictions(const Connection& c, std::int64_t run_id);
std::vector<InstrumentRecord> instruments(const Connection& c);
std::optional<SampleRecord> specimen(const Connection& c, std::int64_t id);
int first_incomplete_step(const Connection& c, std::int64_t run_id);
/// Latest monotonic time recorded in the run (samples, events, steps); nullopt when none.
std::optional<std::int64_t> last_recorded_t_ns(const Connection& c, std::int64_t run_id);

}  // namespace tocd::db::detail

#pragma once

// Queries shared by the server's Database and Reader: one place maps rows to records, as
// rows.hpp does for the SQLite file.

#include <cstdint>
#include <optional>
#include <vector>

#include "pg_util.hpp"
#include "record_rows.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/records.hpp"

namespace tocd::db::pg {

std::optional<RunRecord> find_run(const Connection& c, std::int64_t run_id);
std::vector<RunRecord> all_runs(const Connection& c);
using detail::require_run;  // record_rows.hpp: one for both backends
std::vector<RunAnchor> run_anchors(const Connection& c, std::int64_t run_id);
std::vector<Channel> run_channels(const Connection& c, std::int64_t run_id);
std::vector<StepRecord> run_steps(const Connection& c, std::int64_t run_id);
std::vector<EventRecord> run_events(const Connection& c, std::int64_t run_id);
std::vector<PredictionRecord> run_predictions(const Connection& c, std::int64_t run_id);
std::vector<InstrumentRecord> instruments(const Connection& c);
std::optional<SampleRecord> specimen(const Connection& c, std::int64_t id);
int first_incomplete_step(const Connection& c, std::int64_t run_id);
std::optional<std::int64_t> last_recorded_t_ns(const Connection& c, std::int64_t run_id);
/// True while some session holds the run's recording lock (an advisory lock, released by the
/// server when that session ends, however it ends).
bool run_locked(const Connection& c, std::int64_t run_id);
/// Samples of a channel in range, optionally decimated as Reader::samples describes.
std::vector<Sample> samples(const Connection& c, std::int64_t channel_id, const SampleQuery& q);
std::int64_t sample_count(const Connection& c, std::int64_t channel_id, const SampleQuery& q);

}  // namespace tocd::db::pg

#pragma once

#include <cstdint>
#include <ostream>

#include "tocd/db/reader.hpp"

namespace tocd::db {

enum class CsvTable {
  steps,    // one row per step (1-based): targets, times, per-channel mean/std/n, measured and predicted T
  samples,  // long format: t_ns, segment, t_s (since run start), utc, channel, unit, value
  events,   // t_ns, segment, utc, kind, step (1-based), message
};

/// Writes one table of a run as CSV (RFC 4180 quoting, LF line ends, '.' decimal point,
/// header row). UTC times come from the anchor of the segment each row was recorded in;
/// columns follow the CLI's naming (docs/database.md, "Export").
void write_csv(const Reader& reader, std::int64_t run_id, CsvTable table, std::ostream& out);

struct JsonExportOptions {
  bool include_samples = true;
  /// Per channel; 0 = every sample. Above it samples are decimated (Decimation::mean).
  std::size_t max_points_per_channel = 0;
  int indent = 2;  // -1 = compact
};

/// Writes a run as one JSON document: run (with UTC times), sample, instruments, anchors,
/// channels (with samples as parallel arrays t_ns / value), steps, events, predictions.
/// NaN values are written as null.
void write_json(const Reader& reader, std::int64_t run_id, const JsonExportOptions& options,
                std::ostream& out);

}  // namespace tocd::db

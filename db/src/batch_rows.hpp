#pragma once

// What both backends' batch writers do with a batch's rows: each row whose run is known is
// written, the others are rejected and counted, and `error` names what was rejected. The
// SQLite writer and the server's BatchWriter each pass how they look a run up and how they
// write one row.

#include <cstdint>
#include <span>
#include <string>

#include <fmt/format.h>

#include "tocd/db/records.hpp"

namespace tocd::db::detail {

/// Writes each sample of a known channel with `write(run_id, sample)`; `run_of(channel_id)` is
/// 0 for an unknown channel, whose samples are rejected.
template <class RunOf, class Write>
void write_known_samples(std::span<const Sample> samples, RunOf&& run_of, Write&& write,
                         std::uint64_t& written, std::uint64_t& rejected, std::string& error) {
  std::int64_t last_bad = 0;
  for (const auto& s : samples) {
    const std::int64_t run = run_of(s.channel_id);
    if (run == 0) {
      ++rejected;
      last_bad = s.channel_id;
      continue;
    }
    write(run, s);
    ++written;
  }
  if (last_bad != 0) error = fmt::format("samples for unknown channel id {} were rejected", last_bad);
}

/// Writes each event of a run that `has_run(run_id)` knows with `write(event)`; the others
/// are rejected.
template <class HasRun, class Write>
void write_known_events(std::span<const EventRecord> events, HasRun&& has_run, Write&& write,
                        std::uint64_t& written, std::uint64_t& rejected, std::string& error) {
  for (const auto& e : events) {
    if (!has_run(e.run_id)) {
      ++rejected;
      error = fmt::format("an event for unknown run id {} was rejected", e.run_id);
      continue;
    }
    write(e);
    ++written;
  }
}

}  // namespace tocd::db::detail

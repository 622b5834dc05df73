#pragma once

// The Writer's batch on a PostgreSQL server: samples by COPY (one round trip for the whole
// batch), events by INSERT, one transaction. Used on the writer thread only.

#include <cstdint>
#include <span>
#include <string>
#include <unordered_map>

#include "pg_util.hpp"
#include "tocd/db/records.hpp"

namespace tocd::db::pg {

class BatchWriter {
 public:
  /// Connects and checks the schema (the server database must exist: Database creates it).
  explicit BatchWriter(const std::string& uri);

  /// Commits the batch in one transaction; rows for unknown channels or runs are counted in
  /// `rejected` (and named in `error`), the rest in `written`. Throws DatabaseError when the
  /// transaction fails (nothing of the batch is stored then); a lost connection is reset
  /// first, so that a retry can succeed once the server is back.
  void write(std::span<const Sample> samples, std::span<const EventRecord> events, std::uint64_t& written,
             std::uint64_t& rejected, std::string& error);

 private:
  std::int64_t run_of(std::int64_t channel_id);
  bool has_run(std::int64_t run_id);
  std::int64_t segment_of(std::int64_t run_id);

  Connection c_;
  std::unordered_map<std::int64_t, std::int64_t> channel_run_;  // channel id -> run id (0: unknown)
  std::unordered_map<std::int64_t, std::int64_t> segment_;      // this batch's segment per run
  std::string copy_;                                            // the COPY text, reused
};

}  // namespace tocd::db::pg

#include "pg_batch.hpp"

#include "batch_rows.hpp"
#include "pg_schema.hpp"

namespace tocd::db::pg {

BatchWriter::BatchWriter(const std::string& uri) : c_(uri) {
  require_schema(c_);
}

std::int64_t BatchWriter::run_of(std::int64_t channel_id) {
  const auto it = channel_run_.find(channel_id);
  if (it != channel_run_.end() && it->second != 0) return it->second;
  // Unknown channels are asked again (they may have been added since): a race between
  // add_channel and the first sample cannot lose data.
  return channel_run_[channel_id] = c_.query_int("SELECT run_id FROM channels WHERE id = $1", {channel_id});
}

bool BatchWriter::has_run(std::int64_t run_id) {
  return c_.query_int("SELECT count(*) FROM runs WHERE id = $1", {run_id}) > 0;
}

std::int64_t BatchWriter::segment_of(std::int64_t run_id) {
  // A run's anchor segment cannot change while it records (resume needs it stopped): one
  // look-up per run and batch.
  const auto it = segment_.find(run_id);
  if (it != segment_.end()) return it->second;
  return segment_[run_id] =
             c_.query_int("SELECT coalesce(max(segment), 0) FROM run_anchors WHERE run_id = $1", {run_id});
}

void BatchWriter::write(std::span<const Sample> samples, std::span<const EventRecord> events,
                        std::uint64_t& written, std::uint64_t& rejected, std::string& error) {
  written = rejected = 0;
  if (PQstatus(c_.get()) != CONNECTION_OK) {
    PQreset(c_.get());  // the server restarted or the network came back
    if (PQstatus(c_.get()) != CONNECTION_OK) c_.fail("reconnecting");
    c_.exec("SET client_min_messages = warning; SET TIME ZONE 'UTC'");
  }
  segment_.clear();
  Transaction t(c_);
  copy_.clear();
  detail::write_known_samples(
      samples, [&](std::int64_t channel_id) { return run_of(channel_id); },
      [&](std::int64_t run, const Sample& s) {
        append_copy_value(copy_, run);
        copy_ += '\t';
        append_copy_value(copy_, s.channel_id);
        copy_ += '\t';
        append_copy_value(copy_, s.t_ns);
        copy_ += '\t';
        append_copy_value(copy_, s.value);
        copy_ += '\t';
        append_copy_value(copy_, segment_of(run));
        copy_ += '\n';
      },
      written, rejected, error);
  if (!copy_.empty()) c_.copy_in("COPY samples(run_id, channel_id, t_ns, value, segment) FROM STDIN", copy_);
  detail::write_known_events(
      events, [&](std::int64_t run_id) { return has_run(run_id); },
      [&](const EventRecord& e) {
        c_.query(
            "INSERT INTO events(run_id, t_ns, kind, message, step_index, data_json, segment) "
            "VALUES($1,$2,$3,$4,$5,$6,$7)",
            {e.run_id, e.t_ns, e.kind, e.message,
             e.step_index >= 0 ? Param(e.step_index) : Param(std::nullopt),
             e.data_json.empty() ? Param(std::nullopt) : Param(e.data_json), segment_of(e.run_id)});
      },
      written, rejected, error);
  t.commit();
}

}  // namespace tocd::db::pg

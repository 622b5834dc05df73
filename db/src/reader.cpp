#include "tocd/db/reader.hpp"

#include <algorithm>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "backend_rows.hpp"
#include "pg/pg_schema.hpp"
#include "run_lock.hpp"
#include "schema.hpp"
#include "sqlite_util.hpp"
#include "tocd/core/log.hpp"
#include "tocd/core/printable.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/location.hpp"

namespace tocd::db {

using detail::Statement;

// Either backend: an SQLite file (c, locks) or a PostgreSQL server (server, a read-only
// session). Every public method hands a server's query to the pg:: row functions.
struct Reader::Impl {
  std::string open_note;  // filled by open_read_only before `c` is used
  detail::Connection c;
  std::optional<detail::RunLocks> locks;
  std::unique_ptr<pg::Connection> server;
  mutable std::mutex mu;
  std::vector<std::string> warnings;
  explicit Impl(const std::filesystem::path& p) {
    if (is_server_uri(p.string())) {
      server = std::make_unique<pg::Connection>(p.string(), true);
      pg::require_schema(*server);
      return;
    }
    c = detail::open_read_only(p, &open_note);
    locks.emplace(p, false);
    if (!open_note.empty()) warnings.push_back(open_note);
    if (auto damage = quick_check(p); !damage.empty()) warnings.push_back(std::move(damage));
    for (const auto& w : warnings) logger("db")->warn("{}", w);
  }

  // `read(c)` for a file, `read(*server)` for a server, under the reader's lock: `read` calls
  // the rows:: function that fits the connection it is given.
  template <class Read>
  auto with_backend(Read read) const {
    std::lock_guard lk(mu);
    if (server) return read(std::as_const(*server));
    return read(c);
  }

  std::string quick_check(const std::filesystem::path& p) const {
    const std::vector<std::string> found = detail::quick_check(c);
    if (found.empty()) return {};
    std::string out =
        "'" + p.string() + "' is damaged (SQLite quick_check): what it shows may be incomplete or wrong;";
    for (std::size_t i = 0; i < found.size() && i < 5; ++i) out += " " + found[i] + ";";
    if (found.size() > 5) out += fmt::format(" and {} more;", found.size() - 5);
    out.pop_back();
    return out;
  }
};

namespace {

constexpr const char* kRange = " channel_id = ?1 AND t_ns BETWEEN ?2 AND ?3";

// A server reader's multi-query answers come from one snapshot, as an SQLite read transaction's.
constexpr const char* kSnapshot = "BEGIN ISOLATION LEVEL REPEATABLE READ READ ONLY";

std::vector<RunSummary> server_runs(const pg::Connection& c) {
  const pg::Transaction t(c, kSnapshot);
  const pg::Result counts = c.query(
      "SELECT r.id, (SELECT count(*) FROM steps WHERE run_id = r.id), (SELECT count(*) FROM predictions "
      "WHERE run_id = r.id), (SELECT count(*) FROM events WHERE run_id = r.id) FROM runs r ORDER BY r.id");
  std::vector<RunSummary> out;
  int i = 0;
  for (auto& r : pg::all_runs(c)) {
    RunSummary s;
    for (; i < counts.rows() && counts.i64(i, 0) < r.id; ++i) {
    }
    if (i < counts.rows() && counts.i64(i, 0) == r.id) {
      s.steps = static_cast<int>(counts.i64(i, 1));
      s.predictions = static_cast<int>(counts.i64(i, 2));
      s.events = static_cast<int>(counts.i64(i, 3));
    }
    s.live = r.status == RunStatus::running && pg::run_locked(c, r.id);
    s.run = std::move(r);
    out.push_back(std::move(s));
  }
  return out;
}

void bind_range(Statement& s, std::int64_t channel_id, const SampleQuery& q) {
  s.bind(1, channel_id).bind(2, q.from_t_ns).bind(3, q.to_t_ns);
}

std::vector<Sample> all_samples(const detail::Connection& c, std::int64_t channel_id, const SampleQuery& q) {
  Statement s(c, std::string("SELECT t_ns, value, segment FROM samples WHERE") + kRange + " ORDER BY t_ns");
  bind_range(s, channel_id, q);
  std::vector<Sample> out;
  while (s.step()) out.push_back({channel_id, s.col_int(0), s.col_double(1), static_cast<int>(s.col_int(2))});
  return out;
}

// Buckets of equal time width over [t_min, t_max] of the samples in range.
std::vector<Sample> decimated(const detail::Connection& c, std::int64_t channel_id, const SampleQuery& q) {
  Statement span(c, std::string("SELECT count(*), min(t_ns), max(t_ns) FROM samples WHERE") + kRange);
  bind_range(span, channel_id, q);
  span.step();
  const auto n = span.col_int(0);
  const std::size_t per_bucket = q.decimation == Decimation::min_max ? 2 : 1;
  const auto buckets = static_cast<std::int64_t>(std::max<std::size_t>(1, q.max_points / per_bucket));
  if (n <= static_cast<std::int64_t>(q.max_points)) return all_samples(c, channel_id, q);
  const std::int64_t t0 = span.col_int(1), t1 = span.col_int(2);
  const std::int64_t width = (t1 - t0) / buckets + 1;

  std::vector<Sample> out;
  if (q.decimation == Decimation::mean) {
    // Mean time relative to t0 keeps the average exact in a double.
    Statement s(
        c, std::string(
               "SELECT (t_ns - ?4) / ?5 AS b, avg(t_ns - ?4), avg(value), max(segment) FROM samples WHERE") +
               kRange + " GROUP BY b ORDER BY b");
    bind_range(s, channel_id, q);
    s.bind(4, t0).bind(5, width);
    while (s.step())
      out.push_back({channel_id, t0 + static_cast<std::int64_t>(s.col_double(1)), s.col_double(2),
                     static_cast<int>(s.col_int(3))});
    return out;
  }
  // min_max: SQLite takes the bare column t_ns from the row that holds the min (max) value.
  const auto extreme = [&](const char* fn) {
    Statement s(c, std::string("SELECT (t_ns - ?4) / ?5 AS b, t_ns, ") + fn +
                       "(value), segment FROM samples WHERE" + kRange + " GROUP BY b ORDER BY b");
    bind_range(s, channel_id, q);
    s.bind(4, t0).bind(5, width);
    std::vector<std::pair<std::int64_t, Sample>> v;
    while (s.step())
      v.push_back(
          {s.col_int(0), {channel_id, s.col_int(1), s.col_double(2), static_cast<int>(s.col_int(3))}});
    return v;
  };
  const auto lo = extreme("min"), hi = extreme("max");
  for (std::size_t i = 0; i < lo.size() && i < hi.size(); ++i) {
    Sample a = lo[i].second, b = hi[i].second;
    if (b.t_ns < a.t_ns) std::swap(a, b);
    out.push_back(a);
    if (b.t_ns != a.t_ns) out.push_back(b);
  }
  return out;
}

}  // namespace

Reader::Reader(const std::filesystem::path& db_path) : impl_(std::make_unique<Impl>(db_path)) {}
Reader::~Reader() = default;

const std::vector<std::string>& Reader::warnings() const noexcept {
  return impl_->warnings;
}
Reader::Reader(Reader&&) noexcept = default;
Reader& Reader::operator=(Reader&&) noexcept = default;

std::vector<RunSummary> Reader::runs() const {
  std::lock_guard lk(impl_->mu);
  if (impl_->server) return server_runs(*impl_->server);
  auto& c = impl_->c;
  Statement counts(c,
                   "SELECT (SELECT count(*) FROM steps WHERE run_id = ?1), (SELECT count(*) FROM predictions "
                   "WHERE run_id = ?1), (SELECT count(*) FROM events WHERE run_id = ?1)");
  std::vector<RunSummary> out;
  // One read transaction: the list and its counts describe the same instant.
  c.exec("BEGIN");
  try {
    for (auto& r : detail::all_runs(c)) {
      RunSummary s;
      counts.bind(1, r.id);
      counts.step();
      s.steps = static_cast<int>(counts.col_int(0));
      s.predictions = static_cast<int>(counts.col_int(1));
      s.events = static_cast<int>(counts.col_int(2));
      counts.reset();
      s.live = impl_->locks->is_held(r.id);
      s.run = std::move(r);
      out.push_back(std::move(s));
    }
  } catch (...) {
    c.exec("ROLLBACK");
    throw;
  }
  c.exec("COMMIT");
  return out;
}

std::optional<RunRecord> Reader::find_run(std::int64_t run_id) const {
  return impl_->with_backend([&](const auto& c) { return rows::find_run(c, run_id); });
}

RunRecord Reader::run(std::int64_t run_id) const {
  return impl_->with_backend([&](const auto& c) { return rows::require_run(c, run_id); });
}

std::vector<RunAnchor> Reader::anchors(std::int64_t run_id) const {
  return impl_->with_backend([&](const auto& c) { return rows::run_anchors(c, run_id); });
}

bool Reader::is_live(std::int64_t run_id) const {
  if (impl_->server) {
    std::lock_guard lk(impl_->mu);
    return pg::run_locked(*impl_->server, run_id);
  }
  std::lock_guard lk(impl_->mu);
  return impl_->locks->is_held(run_id);
}

RunStatus Reader::shown_status(std::int64_t run_id) const {
  std::lock_guard lk(impl_->mu);
  const auto stored = [&] {
    return impl_->server ? pg::require_run(*impl_->server, run_id) : detail::require_run(impl_->c, run_id);
  };
  const auto locked = [&] {
    return impl_->server ? pg::run_locked(*impl_->server, run_id) : impl_->locks->is_held(run_id);
  };
  const RunRecord r = stored();
  if (r.status != RunStatus::running || locked()) return r.status;
  // Read again after the lock check: a run that ended in between shows its final status.
  const RunStatus again = stored().status;
  return again == RunStatus::running ? RunStatus::interrupted : again;
}

std::optional<InstrumentRecord> Reader::instrument(std::int64_t instrument_id) const {
  for (auto& i : instruments())
    if (i.id == instrument_id) return i;
  return std::nullopt;
}

std::vector<InstrumentRecord> Reader::instruments() const {
  return impl_->with_backend([](const auto& c) { return rows::instruments(c); });
}

std::optional<SampleRecord> Reader::sample(std::int64_t sample_id) const {
  return impl_->with_backend([&](const auto& c) { return rows::specimen(c, sample_id); });
}

std::vector<Channel> Reader::channels(std::int64_t run_id) const {
  return impl_->with_backend([&](const auto& c) { return rows::run_channels(c, run_id); });
}

std::optional<Channel> Reader::channel(std::int64_t run_id, const std::string& name) const {
  for (auto& ch : channels(run_id))
    if (ch.name == name) return ch;
  return std::nullopt;
}

std::vector<Sample> Reader::samples(std::int64_t channel_id, const SampleQuery& q) const {
  if (impl_->server) {
    std::lock_guard lk(impl_->mu);
    const pg::Transaction t(*impl_->server, kSnapshot);  // the span and the buckets from one snapshot
    return pg::samples(*impl_->server, channel_id, q);
  }
  std::lock_guard lk(impl_->mu);
  if (q.decimation == Decimation::none) return all_samples(impl_->c, channel_id, q);
  impl_->c.exec("BEGIN");  // the span and the buckets from one snapshot
  try {
    auto out = decimated(impl_->c, channel_id, q);
    impl_->c.exec("COMMIT");
    return out;
  } catch (...) {
    impl_->c.exec("ROLLBACK");
    throw;
  }
}

std::int64_t Reader::sample_count(std::int64_t channel_id, const SampleQuery& q) const {
  if (impl_->server) {
    std::lock_guard lk(impl_->mu);
    return pg::sample_count(*impl_->server, channel_id, q);
  }
  std::lock_guard lk(impl_->mu);
  Statement s(impl_->c, std::string("SELECT count(*) FROM samples WHERE") + kRange);
  bind_range(s, channel_id, q);
  s.step();
  return s.col_int(0);
}

std::vector<StepRecord> Reader::steps(std::int64_t run_id) const {
  if (impl_->server) {
    std::lock_guard lk(impl_->mu);
    const pg::Transaction t(*impl_->server, kSnapshot);  // steps and their statistics together
    return pg::run_steps(*impl_->server, run_id);
  }
  std::lock_guard lk(impl_->mu);
  return detail::run_steps(impl_->c, run_id);
}

std::vector<EventRecord> Reader::events(std::int64_t run_id) const {
  return impl_->with_backend([&](const auto& c) { return rows::run_events(c, run_id); });
}

std::vector<PredictionRecord> Reader::predictions(std::int64_t run_id) const {
  return impl_->with_backend([&](const auto& c) { return rows::run_predictions(c, run_id); });
}

namespace {

void read_steps_and_predictions(const detail::Connection& c, std::int64_t run_id, std::vector<StepRecord>& st,
                                std::vector<PredictionRecord>& pr) {
  c.exec("BEGIN");
  try {
    st = detail::run_steps(c, run_id);
    pr = detail::run_predictions(c, run_id);
  } catch (...) {
    c.exec("ROLLBACK");
    throw;
  }
  c.exec("COMMIT");
}

std::vector<CompareRow> compare_rows(std::vector<StepRecord> st, const std::vector<PredictionRecord>& pr) {
  std::vector<CompareRow> out;
  for (auto& s : st) {
    // A step cut short (re-recorded or left incomplete; older runs stored such rows) is not a
    // measurement: compare, export and the GUI list completed steps only.
    if (!s.completed) continue;
    CompareRow row;
    // Predictions come ordered by (step, id): the last match is the latest.
    for (const auto& p : pr)
      if (p.step_index == s.index) row.prediction = p;
    if (row.prediction && s.measured_transmission != 0)
      row.relative_difference = (row.prediction->T - s.measured_transmission) / s.measured_transmission;
    row.step = std::move(s);
    out.push_back(std::move(row));
  }
  return out;
}

}  // namespace

std::vector<CompareRow> Reader::compare(std::int64_t run_id) const {
  std::vector<StepRecord> st;
  std::vector<PredictionRecord> pr;
  {
    std::lock_guard lk(impl_->mu);
    if (impl_->server) {
      const pg::Transaction t(*impl_->server, kSnapshot);
      st = pg::run_steps(*impl_->server, run_id);
      pr = pg::run_predictions(*impl_->server, run_id);
    } else {
      read_steps_and_predictions(impl_->c, run_id, st, pr);
    }
  }
  return compare_rows(std::move(st), pr);
}

int Reader::first_incomplete_step(std::int64_t run_id) const {
  return impl_->with_backend([&](const auto& c) { return rows::first_incomplete_step(c, run_id); });
}

}  // namespace tocd::db

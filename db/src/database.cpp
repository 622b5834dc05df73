#include "tocd/db/database.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <unistd.h>

#include "backend_rows.hpp"
#include "pg/pg_database.hpp"
#include "resume_plan.hpp"
#include "run_lock.hpp"
#include "schema.hpp"
#include "sqlite_util.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/log.hpp"
#include "tocd/core/version.hpp"
#include "tocd/db/location.hpp"
#include "uuid.hpp"

namespace tocd::db {

using detail::Statement;
using detail::Transaction;

// Either backend: an SQLite file (c, locks) or a PostgreSQL server (server). Every public
// method hands a server's call to PgDatabase, which keeps the same contracts.
struct Database::Impl {
  std::filesystem::path path;
  detail::Connection c;
  std::optional<detail::RunLocks> locks;
  std::unique_ptr<pg::PgDatabase> server;
  std::vector<std::int64_t> interrupted;
  std::string journal_mode;
  mutable std::mutex mu;

  Impl(const std::filesystem::path& p, detail::Connection conn) : path(p), c(std::move(conn)) {
    locks.emplace(p, true);
  }
  Impl(const std::filesystem::path& uri, std::unique_ptr<pg::PgDatabase> pg)
      : path(uri),
        server(std::move(pg)),
        interrupted(server->interrupted_on_open()),
        journal_mode("server") {}

  // At rest a database is one file: the last writer to close takes it out of WAL (checkpoint,
  // rollback journal), so that readers, which open it read-only, find no WAL and leave no
  // -wal and -shm files beside a file they only read. The next writer turns WAL on again.
  // With another connection open (a reader, a second writer) SQLite refuses at once (no
  // busy wait here) and the file stays in WAL until that one's writer closes.
  ~Impl() {
    if (!c.get()) return;
    sqlite3_busy_timeout(c.get(), 0);
    char* error = nullptr;
    if (sqlite3_exec(c.get(), "PRAGMA journal_mode=DELETE", nullptr, nullptr, &error) != SQLITE_OK)
      logger("db")->debug("'{}' stays in WAL at close: {}", path.string(), error ? error : "busy");
    sqlite3_free(error);
  }

  std::int64_t insert_event(const EventRecord& e) {
    Statement s(c,
                "INSERT INTO events(run_id, t_ns, kind, message, step_index, data_json, segment) "
                "VALUES(?1,?2,?3,?4,?5,?6,"
                "(SELECT coalesce(max(segment), 0) FROM run_anchors WHERE run_id = ?1))");
    s.bind(1, e.run_id).bind(2, e.t_ns).bind(3, e.kind).bind(4, e.message);
    if (e.step_index >= 0) s.bind(5, e.step_index);
    if (!e.data_json.empty()) s.bind(6, e.data_json);
    s.run();
    return sqlite3_last_insert_rowid(c.get());
  }

  void add_anchor(std::int64_t run_id, std::int64_t wall, std::int64_t mono, double clock_factor) {
    Statement s(c,
                "INSERT INTO run_anchors(run_id, segment, wall_utc_ns, monotonic_ns, clock_factor) VALUES(?, "
                "(SELECT coalesce(max(segment) + 1, 0) FROM run_anchors WHERE run_id = ?), ?, ?, ?)");
    s.bind(1, run_id).bind(2, run_id).bind(3, wall).bind(4, mono).bind(5, clock_factor).run();
  }

  // Runs left `running` by a process that no longer holds their lock were cut off.
  void mark_interrupted() {
    std::vector<RunRecord> stale;
    for (auto& r : detail::all_runs(c))
      if (r.status == RunStatus::running && !locks->is_held(r.id)) stale.push_back(std::move(r));
    if (stale.empty()) return;
    Transaction t(c);
    for (const auto& r : stale) {
      const detail::CutOff cut =
          detail::cut_off(r, detail::run_anchors(c, r.id), detail::last_recorded_t_ns(c, r.id));
      Statement u(c, "UPDATE runs SET status = 'interrupted', ended_utc_ns = ? WHERE id = ?");
      if (cut.ended_utc_ns) u.bind(1, *cut.ended_utc_ns);
      u.bind(2, r.id).run();
      insert_event(cut.event);
      interrupted.push_back(r.id);
    }
    t.commit();
    for (auto id : interrupted) logger("db")->warn("run {} was left running; marked interrupted", id);
  }
};

Database Database::open(const std::filesystem::path& path) {
  return Database(path);
}

namespace {

// Recording needs the file and, for WAL's -wal and -shm files, its directory writable. Said
// up front, instead of SQLite's "attempt to write a readonly database" halfway through.
void require_writable(const std::filesystem::path& path) {
  const auto dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  const bool file_ok = !std::filesystem::exists(path) || ::access(path.c_str(), W_OK) == 0;
  if (!file_ok || ::access(dir.c_str(), W_OK) != 0)
    throw DatabaseError(
        fmt::format("'{}' cannot be written here ({} is read-only); commands that only read it "
                    "(runs, compare, export) still can",
                    path.string(), file_ok ? "its directory" : "the file"));
}

}  // namespace

Database::Database(const std::filesystem::path& path) {
  if (is_server_uri(path.string())) {
    impl_ = std::make_unique<Impl>(path, std::make_unique<pg::PgDatabase>(path.string()));
    return;
  }
  detail::identify(path);  // refuses foreign and newer files before anything is written
  require_writable(path);
  const bool existed = std::filesystem::exists(path) && std::filesystem::file_size(path) > 0;
  detail::Connection c(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  // A damaged file is refused before anything is written into it (or anything moves on a rig
  // whose run would record into it): SQLite would fail mid-run on the first damaged page it
  // touches, or write beside the damage and leave it for later.
  if (existed) {
    if (const auto damage = detail::quick_check(c); !damage.empty()) {
      std::string found;
      for (std::size_t i = 0; i < damage.size() && i < 3; ++i) found += (i ? "; " : "") + damage[i];
      throw DatabaseError(fmt::format(
          "'{}' is damaged (SQLite quick_check: {}); nothing was written to it. Record into another "
          "file (--db NEW.db); what this one still holds can be read with tocdlab runs/export, or "
          "copied out with: sqlite3 '{}' .recover | sqlite3 recovered.db",
          path.string(), found, path.string()));
    }
  }
  std::string journal_mode = detail::configure_read_write(c);
  detail::migrate(c);
  impl_ = std::make_unique<Impl>(path, std::move(c));
  impl_->journal_mode = std::move(journal_mode);
  impl_->mark_interrupted();
}

Database::~Database() = default;
Database::Database(Database&&) noexcept = default;
Database& Database::operator=(Database&&) noexcept = default;

const std::filesystem::path& Database::path() const noexcept {
  return impl_->path;
}

int Database::schema_version() const {
  if (impl_->server) return impl_->server->schema_version();
  std::lock_guard lk(impl_->mu);
  return static_cast<int>(impl_->c.query_int("PRAGMA user_version"));
}

const std::string& Database::journal_mode() const noexcept {
  return impl_->journal_mode;
}

const std::vector<std::int64_t>& Database::interrupted_on_open() const noexcept {
  return impl_->interrupted;
}

std::string Database::integrity_check() const {
  if (impl_->server) return impl_->server->integrity_check();
  std::lock_guard lk(impl_->mu);
  Statement s(impl_->c, "PRAGMA integrity_check");
  std::string out;
  while (s.step()) out += (out.empty() ? "" : "\n") + s.col_text(0);
  return out;
}

std::int64_t Database::add_instrument(const InstrumentRecord& in) {
  if (impl_->server) return impl_->server->add_instrument(in);
  std::lock_guard lk(impl_->mu);
  Statement s(impl_->c,
              "INSERT INTO instruments(kind, model, serial, firmware, calibration) VALUES(?,?,?,?,?) "
              "ON CONFLICT(model, serial) DO UPDATE SET kind = excluded.kind, firmware = excluded.firmware, "
              "calibration = excluded.calibration RETURNING id");
  s.bind(1, in.kind).bind(2, in.model).bind(3, in.serial).bind(4, in.firmware).bind(5, in.calibration);
  if (!s.step()) throw DatabaseError("adding instrument '" + in.model + "' returned no id");
  const auto id = s.col_int(0);
  s.run();
  return id;
}

std::int64_t Database::add_sample(const SampleRecord& sp) {
  if (impl_->server) return impl_->server->add_sample(sp);
  std::lock_guard lk(impl_->mu);
  Statement s(impl_->c, "INSERT INTO specimens(name, tissue, thickness_mm, notes) VALUES(?,?,?,?)");
  s.bind(1, sp.name).bind(2, sp.tissue).bind(3, sp.thickness_mm).bind(4, sp.notes).run();
  return sqlite3_last_insert_rowid(impl_->c.get());
}

namespace {

std::string host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

}  // namespace

RunRecord Database::create_run(const NewRun& in) {
  std::lock_guard lk(impl_->mu);
  RunRecord r;
  r.uuid = detail::random_uuid();
  r.name = in.name;
  r.sample_id = in.sample_id;
  r.protocol_text = in.protocol_text;
  r.lab_config_text = in.lab_config_text;
  r.software_version = in.software_version.empty() ? std::string(tocd::version()) : in.software_version;
  r.operator_name = in.operator_name;
  r.baseline_power_W = in.baseline_power_W;
  // The anchor pair: both clocks read back to back (sub-microsecond apart).
  r.monotonic_anchor_ns = monotonic_ns();
  r.wall_anchor_utc_ns = wall_clock_ns();
  r.started_utc_ns = r.wall_anchor_utc_ns;
  r.status = RunStatus::running;
  r.host = host_name();
  r.software_commit = std::string(tocd::git_commit());
  r.settings = in.settings;
  if (!(in.clock_factor > 0.0) || !std::isfinite(in.clock_factor))
    throw DatabaseError(
        fmt::format("a run's clock factor must be a positive number, got {}", in.clock_factor));
  r.clock_factor = in.clock_factor;
  if (impl_->server) return impl_->server->create_run(in, r);

  Transaction t(impl_->c);
  Statement s(impl_->c,
              "INSERT INTO runs(uuid, name, specimen_id, protocol, lab_config, software_version, operator, "
              "baseline_power_W, wall_anchor_utc_ns, monotonic_anchor_ns, started_utc_ns, host, "
              "software_commit, status) VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,'running')");
  s.bind(1, r.uuid)
      .bind(2, r.name)
      .bind_id(3, r.sample_id)
      .bind(4, r.protocol_text)
      .bind(5, r.lab_config_text);
  s.bind(6, r.software_version).bind(7, r.operator_name).bind(8, r.baseline_power_W);
  s.bind(9, r.wall_anchor_utc_ns).bind(10, r.monotonic_anchor_ns).bind(11, r.started_utc_ns);
  s.bind(12, r.host).bind(13, r.software_commit).run();
  r.id = sqlite3_last_insert_rowid(impl_->c.get());
  Statement setting(impl_->c, "INSERT INTO run_settings(run_id, key, value) VALUES(?,?,?)");
  for (const auto& [key, value] : r.settings) {
    setting.bind(1, r.id).bind(2, key).bind(3, value).run();
    setting.reset();
  }
  impl_->add_anchor(r.id, r.wall_anchor_utc_ns, r.monotonic_anchor_ns, r.clock_factor);
  // Lock before commit: from the moment the run is visible as running, it is visibly live.
  if (!impl_->locks->acquire(r.id))
    throw DatabaseError(fmt::format("run {} is already locked by another process", r.id));
  t.commit();
  return r;
}

void Database::set_run_status(std::int64_t run_id, RunStatus status) {
  if (status == RunStatus::running)
    throw DatabaseError("a run cannot be set back to running; use resume (run " + std::to_string(run_id) +
                        ")");
  if (impl_->server) return impl_->server->set_run_status(run_id, status);
  std::lock_guard lk(impl_->mu);
  detail::require_run(impl_->c, run_id);
  Statement s(impl_->c, "UPDATE runs SET status = ?, ended_utc_ns = ? WHERE id = ?");
  s.bind(1, to_string(status)).bind(2, wall_clock_ns()).bind(3, run_id).run();
  impl_->locks->release(run_id);
}

void Database::mark_run_ended(std::int64_t run_id) {
  if (impl_->server) return impl_->server->mark_run_ended(run_id);
  std::lock_guard lk(impl_->mu);
  detail::require_run(impl_->c, run_id);
  Statement s(impl_->c, "UPDATE runs SET ended_utc_ns = ? WHERE id = ? AND status <> 'running'");
  s.bind(1, wall_clock_ns()).bind(2, run_id).run();
}

void Database::set_baseline_power(std::int64_t run_id, double baseline_power_W) {
  if (impl_->server) return impl_->server->set_baseline_power(run_id, baseline_power_W);
  std::lock_guard lk(impl_->mu);
  detail::require_run(impl_->c, run_id);
  Statement s(impl_->c, "UPDATE runs SET baseline_power_W = ? WHERE id = ?");
  s.bind(1, baseline_power_W).bind(2, run_id).run();
}

ResumePoint Database::resume_run(std::int64_t run_id, double clock_factor) {
  if (!(clock_factor > 0.0) || !std::isfinite(clock_factor))
    throw DatabaseError(fmt::format("a run's clock factor must be a positive number, got {}", clock_factor));
  if (impl_->server) return impl_->server->resume_run(run_id, clock_factor);
  std::lock_guard lk(impl_->mu);
  RunRecord r = detail::require_run(impl_->c, run_id);
  detail::require_resumable(r, [&] { return impl_->locks->is_held(run_id); });
  if (!impl_->locks->acquire(run_id))
    throw DatabaseError(fmt::format("run {} is being resumed by another process", run_id));
  try {
    Transaction t(impl_->c);
    auto [p, wall] = rows::plan_resume_now(impl_->c, r);
    impl_->add_anchor(run_id, wall, p.gap_to_t_ns, clock_factor);
    Statement s(impl_->c, "UPDATE runs SET status = 'running', ended_utc_ns = NULL WHERE id = ?");
    s.bind(1, run_id).run();
    p.gap_event.id = impl_->insert_event(p.gap_event);
    t.commit();
    return detail::resumed(std::move(p), std::move(r));
  } catch (...) {
    impl_->locks->release(run_id);
    throw;
  }
}

bool Database::is_live(std::int64_t run_id) const {
  if (impl_->server) return impl_->server->is_live(run_id);
  std::lock_guard lk(impl_->mu);
  return impl_->locks->is_held(run_id);
}

Channel Database::add_channel(const Channel& ch) {
  if (impl_->server) return impl_->server->add_channel(ch);
  std::lock_guard lk(impl_->mu);
  detail::require_run(impl_->c, ch.run_id);
  Statement s(impl_->c,
              "INSERT INTO channels(run_id, name, unit, instrument_id, nominal_rate_Hz) VALUES(?,?,?,?,?)");
  s.bind(1, ch.run_id)
      .bind(2, ch.name)
      .bind(3, ch.unit)
      .bind_id(4, ch.instrument_id)
      .bind(5, ch.nominal_rate_Hz);
  try {
    s.run();
  } catch (const DatabaseError& e) {
    throw DatabaseError(fmt::format("cannot add channel '{}' to run {}: {}", ch.name, ch.run_id, e.what()));
  }
  Channel out = ch;
  out.id = sqlite3_last_insert_rowid(impl_->c.get());
  return out;
}

std::int64_t Database::add_step(const StepRecord& st) {
  if (impl_->server) return impl_->server->add_step(st);
  std::lock_guard lk(impl_->mu);
  auto& c = impl_->c;
  detail::require_run(c, st.run_id);
  Transaction t(c);
  Statement del(c, "DELETE FROM steps WHERE run_id = ? AND step_index = ?");  // stats cascade
  del.bind(1, st.run_id).bind(2, st.index).run();
  Statement s(
      c,
      "INSERT INTO steps(run_id, step_index, target_displacement_mm, nominal_strain, target_pressure_kPa, "
      "started_t_ns, settled_t_ns, recorded_from_t_ns, recorded_to_t_ns, measured_transmission, completed) "
      "VALUES(?,?,?,?,?,?,?,?,?,?,?)");
  s.bind(1, st.run_id).bind(2, st.index).bind(3, st.target_displacement_mm).bind(4, st.nominal_strain);
  s.bind(5, st.target_pressure_kPa).bind(6, st.started_t_ns).bind(7, st.settled_t_ns);
  s.bind(8, st.recorded_from_t_ns).bind(9, st.recorded_to_t_ns).bind(10, st.measured_transmission);
  s.bind(11, st.completed ? 1 : 0).run();
  const auto id = sqlite3_last_insert_rowid(c.get());
  Statement x(c, "INSERT INTO step_channel_stats(step_id, channel_id, mean, std, n) VALUES(?,?,?,?,?)");
  for (const auto& cs : st.channels) {
    try {
      x.bind(1, id).bind(2, cs.channel_id).bind(3, cs.mean).bind(4, cs.std).bind(5, cs.n).run();
    } catch (const DatabaseError& e) {
      throw DatabaseError(fmt::format("step {} of run {}: statistics for channel {}: {}", st.index, st.run_id,
                                      cs.channel_id, e.what()));
    }
    x.reset();
  }
  t.commit();
  return id;
}

std::int64_t Database::add_event(const EventRecord& e) {
  if (impl_->server) return impl_->server->add_event(e);
  std::lock_guard lk(impl_->mu);
  try {
    return impl_->insert_event(e);
  } catch (const DatabaseError& err) {
    throw DatabaseError(fmt::format("cannot record event '{}' of run {}: {}", e.kind, e.run_id, err.what()));
  }
}

std::int64_t Database::add_prediction(const PredictionRecord& p) {
  if (impl_->server) return impl_->server->add_prediction(p);
  std::lock_guard lk(impl_->mu);
  detail::require_run(impl_->c, p.run_id);
  Statement s(
      impl_->c,
      "INSERT INTO predictions(run_id, step_index, config_json, T, T_stderr, fe_seconds, mesh_seconds, "
      "mc_seconds, total_seconds, software_version, summary_json, created_utc_ns, latency_s) "
      "VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?)");
  s.bind(1, p.run_id).bind(2, p.step_index).bind(3, p.config_json).bind(4, p.T).bind(5, p.T_stderr);
  s.bind(6, p.fe_seconds).bind(7, p.mesh_seconds).bind(8, p.mc_seconds).bind(9, p.total_seconds);
  s.bind(10, p.software_version.empty() ? std::string(tocd::version()) : p.software_version);
  if (!p.summary_json.empty()) s.bind(11, p.summary_json);
  s.bind(12, p.created_utc_ns != 0 ? p.created_utc_ns : wall_clock_ns());
  s.bind(13, p.latency_s).run();
  return sqlite3_last_insert_rowid(impl_->c.get());
}

int Database::first_incomplete_step(std::int64_t run_id) const {
  if (impl_->server) return impl_->server->first_incomplete_step(run_id);
  std::lock_guard lk(impl_->mu);
  return detail::first_incomplete_step(impl_->c, run_id);
}

RunRecord Database::run(std::int64_t run_id) const {
  if (impl_->server) return impl_->server->run(run_id);
  std::lock_guard lk(impl_->mu);
  return detail::require_run(impl_->c, run_id);
}

}  // namespace tocd::db

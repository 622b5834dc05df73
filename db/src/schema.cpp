#include "schema.hpp"

#include <array>
#include <string>

#include <fmt/format.h>

#include "tocd/core/clock.hpp"
#include "tocd/core/log.hpp"
#include "tocd/core/version.hpp"

namespace tocd::db::detail {

namespace {

// Migration i brings a file from version i to version i + 1. Never edit a released entry:
// append a new one and bump Database::kSchemaVersion (docs/database.md lists them).
constexpr std::array<const char*, Database::kSchemaVersion> kMigrations = {
    // 0 -> 1: the initial schema.
    R"sql(
CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE instruments(
  id INTEGER PRIMARY KEY, kind TEXT NOT NULL DEFAULT '', model TEXT NOT NULL, serial TEXT NOT NULL,
  firmware TEXT NOT NULL DEFAULT '', calibration TEXT NOT NULL DEFAULT '', UNIQUE(model, serial));
CREATE TABLE specimens(
  id INTEGER PRIMARY KEY, name TEXT NOT NULL DEFAULT '', tissue TEXT NOT NULL DEFAULT '',
  thickness_mm REAL, notes TEXT NOT NULL DEFAULT '');
CREATE TABLE runs(
  id INTEGER PRIMARY KEY, uuid TEXT NOT NULL UNIQUE, name TEXT NOT NULL DEFAULT '',
  specimen_id INTEGER REFERENCES specimens(id), protocol TEXT NOT NULL, lab_config TEXT NOT NULL,
  software_version TEXT NOT NULL, operator TEXT NOT NULL DEFAULT '', baseline_power_W REAL,
  wall_anchor_utc_ns INTEGER NOT NULL, monotonic_anchor_ns INTEGER NOT NULL,
  started_utc_ns INTEGER NOT NULL, ended_utc_ns INTEGER,
  status TEXT NOT NULL CHECK(status IN ('running', 'completed', 'aborted', 'interrupted')));
CREATE TABLE run_anchors(
  run_id INTEGER NOT NULL REFERENCES runs(id), segment INTEGER NOT NULL,
  wall_utc_ns INTEGER NOT NULL, monotonic_ns INTEGER NOT NULL, PRIMARY KEY(run_id, segment));
CREATE TABLE channels(
  id INTEGER PRIMARY KEY, run_id INTEGER NOT NULL REFERENCES runs(id), name TEXT NOT NULL,
  unit TEXT NOT NULL DEFAULT '', instrument_id INTEGER REFERENCES instruments(id),
  nominal_rate_Hz REAL, UNIQUE(run_id, name));
CREATE TABLE samples(
  run_id INTEGER NOT NULL, channel_id INTEGER NOT NULL, t_ns INTEGER NOT NULL, value REAL);
CREATE INDEX samples_by_channel_time ON samples(channel_id, t_ns);
CREATE TABLE steps(
  id INTEGER PRIMARY KEY, run_id INTEGER NOT NULL REFERENCES runs(id), step_index INTEGER NOT NULL,
  target_displacement_mm REAL, nominal_strain REAL, target_pressure_kPa REAL,
  started_t_ns INTEGER, settled_t_ns INTEGER, recorded_from_t_ns INTEGER, recorded_to_t_ns INTEGER,
  measured_transmission REAL, completed INTEGER NOT NULL, UNIQUE(run_id, step_index));
CREATE TABLE step_channel_stats(
  step_id INTEGER NOT NULL REFERENCES steps(id) ON DELETE CASCADE,
  channel_id INTEGER NOT NULL REFERENCES channels(id), mean REAL, std REAL, n INTEGER NOT NULL,
  PRIMARY KEY(step_id, channel_id));
CREATE TABLE events(
  id INTEGER PRIMARY KEY, run_id INTEGER NOT NULL REFERENCES runs(id), t_ns INTEGER NOT NULL,
  kind TEXT NOT NULL, message TEXT NOT NULL DEFAULT '', step_index INTEGER, data_json TEXT);
CREATE INDEX events_by_run_time ON events(run_id, t_ns);
CREATE TABLE predictions(
  id INTEGER PRIMARY KEY, run_id INTEGER NOT NULL REFERENCES runs(id), step_index INTEGER NOT NULL,
  config_json TEXT NOT NULL, T REAL, T_stderr REAL, fe_seconds REAL, mesh_seconds REAL,
  mc_seconds REAL, total_seconds REAL, software_version TEXT NOT NULL, summary_json TEXT,
  created_utc_ns INTEGER NOT NULL);
CREATE INDEX predictions_by_run_step ON predictions(run_id, step_index);
)sql",
    // 1 -> 2: the anchor segment of every sample and event (its UTC comes from that segment's
    // anchor); run metadata (host, software commit, instrument settings); the views pandas
    // reads (docs/database.md, "Views").
    R"sql(
ALTER TABLE samples ADD COLUMN segment INTEGER NOT NULL DEFAULT 0;
ALTER TABLE events ADD COLUMN segment INTEGER NOT NULL DEFAULT 0;
-- Schema 1 did not store the segment. Within one boot of the recording machine the latest
-- anchor at or before a time is its segment (each resume anchors after everything before it).
UPDATE samples SET segment = (SELECT max(a.segment) FROM run_anchors a
  WHERE a.run_id = samples.run_id AND a.monotonic_ns <= samples.t_ns)
  WHERE run_id IN (SELECT run_id FROM run_anchors WHERE segment > 0)
    AND EXISTS (SELECT 1 FROM run_anchors a WHERE a.run_id = samples.run_id AND a.monotonic_ns <= samples.t_ns);
UPDATE events SET segment = (SELECT max(a.segment) FROM run_anchors a
  WHERE a.run_id = events.run_id AND a.monotonic_ns <= events.t_ns)
  WHERE run_id IN (SELECT run_id FROM run_anchors WHERE segment > 0)
    AND EXISTS (SELECT 1 FROM run_anchors a WHERE a.run_id = events.run_id AND a.monotonic_ns <= events.t_ns);
ALTER TABLE runs ADD COLUMN host TEXT NOT NULL DEFAULT '';
ALTER TABLE runs ADD COLUMN software_commit TEXT NOT NULL DEFAULT '';
CREATE TABLE run_settings(
  run_id INTEGER NOT NULL REFERENCES runs(id), key TEXT NOT NULL, value TEXT NOT NULL,
  PRIMARY KEY(run_id, key));

-- Every sample of every run in long form, with its UTC from the anchor of its own segment.
-- t_s: seconds since the run started, on the UTC axis (continuous across resumes).
CREATE VIEW sample_series AS
SELECT s.run_id, s.segment, ch.name AS channel, ch.unit, s.t_ns,
       a.wall_utc_ns + (s.t_ns - a.monotonic_ns) AS utc_ns,
       (a.wall_utc_ns + (s.t_ns - a.monotonic_ns) - r.started_utc_ns) * 1e-9 AS t_s,
       strftime('%Y-%m-%dT%H:%M:%fZ', (a.wall_utc_ns + (s.t_ns - a.monotonic_ns)) / 1000000 / 1000.0,
                'unixepoch') AS utc,
       s.value
FROM samples s
JOIN channels ch ON ch.id = s.channel_id
JOIN runs r ON r.id = s.run_id
JOIN run_anchors a ON a.run_id = s.run_id AND a.segment = s.segment;

-- Every step of every run next to its latest prediction. Measured values only for completed
-- steps (state 'completed'); a step cut short keeps its targets and its state, nothing else.
-- measured_T_se: standard error of the mean power over the recording window divided by the
-- baseline power (readings taken as independent).
CREATE VIEW step_comparison AS
SELECT st.run_id, st.step_index + 1 AS step,
       CASE WHEN st.completed THEN 'completed' ELSE 'incomplete' END AS state,
       st.target_displacement_mm,
       CASE WHEN st.completed THEN d.mean END AS displacement_mm,
       st.nominal_strain, st.target_pressure_kPa,
       CASE WHEN st.completed THEN l.mean END AS load_N,
       CASE WHEN st.completed THEN p.mean END AS power_W,
       r.baseline_power_W,
       CASE WHEN st.completed THEN st.measured_transmission END AS measured_T,
       CASE WHEN st.completed AND p.n > 1 AND r.baseline_power_W > 0
            THEN p.std / sqrt(p.n) / r.baseline_power_W END AS measured_T_se,
       pr.T AS predicted_T, pr.T_stderr AS predicted_T_se,
       CASE WHEN st.completed AND st.measured_transmission <> 0
            THEN (pr.T - st.measured_transmission) / st.measured_transmission END AS relative_difference
FROM steps st
JOIN runs r ON r.id = st.run_id
LEFT JOIN channels dch ON dch.run_id = st.run_id AND dch.name = 'displacement'
LEFT JOIN step_channel_stats d ON d.step_id = st.id AND d.channel_id = dch.id
LEFT JOIN channels lch ON lch.run_id = st.run_id AND lch.name = 'load'
LEFT JOIN step_channel_stats l ON l.step_id = st.id AND l.channel_id = lch.id
LEFT JOIN channels pch ON pch.run_id = st.run_id AND pch.name = 'power'
LEFT JOIN step_channel_stats p ON p.step_id = st.id AND p.channel_id = pch.id
LEFT JOIN predictions pr ON pr.id = (SELECT max(id) FROM predictions
                                     WHERE run_id = st.run_id AND step_index = st.step_index);

-- The measurements: completed steps only (a recorded step is a fact only when completed).
CREATE VIEW measurements AS
SELECT run_id, step, target_displacement_mm, displacement_mm, nominal_strain, target_pressure_kPa,
       load_N, power_W, baseline_power_W, measured_T, measured_T_se, predicted_T, predicted_T_se,
       relative_difference
FROM step_comparison WHERE state = 'completed';
)sql",
    // 2 -> 3: the run's clock rate with each anchor. A simulated lab may run its clock faster
    // than real time; samples keep that clock in t_ns, and UTC divides it out so every UTC is
    // real time. Runs written before version 3 did not store the rate: they read as 1.
    R"sql(
ALTER TABLE run_anchors ADD COLUMN clock_factor REAL NOT NULL DEFAULT 1.0 CHECK(clock_factor > 0);
DROP VIEW sample_series;
-- Every sample of every run in long form. utc_ns / utc / t_s: real time, from the anchor of
-- the sample's own segment (t_s: seconds since the run started, continuous across resumes).
-- clock_s: the same instant on the run's own clock (t_ns) since the run started; it differs
-- from t_s when a simulated lab ran its clock clock_factor times faster than real time.
CREATE VIEW sample_series AS
SELECT s.run_id, s.segment, ch.name AS channel, ch.unit, s.t_ns,
       a.wall_utc_ns + CAST(round((s.t_ns - a.monotonic_ns) / a.clock_factor) AS INTEGER) AS utc_ns,
       (a.wall_utc_ns + CAST(round((s.t_ns - a.monotonic_ns) / a.clock_factor) AS INTEGER) - r.started_utc_ns)
           * 1e-9 AS t_s,
       strftime('%Y-%m-%dT%H:%M:%fZ',
                (a.wall_utc_ns + CAST(round((s.t_ns - a.monotonic_ns) / a.clock_factor) AS INTEGER)) / 1000000
                    / 1000.0,
                'unixepoch') AS utc,
       (s.t_ns - r.monotonic_anchor_ns) * 1e-9 AS clock_s,
       a.clock_factor,
       s.value
FROM samples s
JOIN channels ch ON ch.id = s.channel_id
JOIN runs r ON r.id = s.run_id
JOIN run_anchors a ON a.run_id = s.run_id AND a.segment = s.segment;
)sql",
    // 3 -> 4: each prediction's latency, real seconds from its step reaching the run's
    // prediction queue to the prediction being stored. Older predictions were not timed so:
    // they read NULL (unset), never 0.
    R"sql(
ALTER TABLE predictions ADD COLUMN latency_s REAL;
)sql",
};

std::string hex(std::int64_t v) {
  return fmt::format("0x{:08X}", static_cast<std::uint32_t>(v));
}

}  // namespace

FileIdentity identify(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (!fs::exists(status)) return {true, 0};
  if (!fs::is_regular_file(status))
    throw DatabaseError("'" + path.string() + "' is not a regular file, so not a tocdlab database");
  if (fs::file_size(path, ec) == 0 && !ec) return {true, 0};

  std::string note;  // opened immutable: the caller that keeps a connection says so
  Connection c = open_existing_read_only(path, note);
  const std::string name = "'" + path.string() + "'";
  std::int64_t app_id = 0, version = 0, objects = 0;
  try {
    app_id = c.query_int("PRAGMA application_id");
    version = c.query_int("PRAGMA user_version");
    objects = c.query_int("SELECT count(*) FROM sqlite_master");
  } catch (const DatabaseError& e) {
    throw DatabaseError(name + " is not a tocdlab database (not a readable SQLite file: " +
                        sqlite3_errmsg(c.get()) + "); it was left untouched");
  }
  if (app_id != Database::kApplicationId) {
    if (app_id == 0 && objects == 0 && version == 0) return {true, 0};
    throw DatabaseError(
        fmt::format("{} is an SQLite database of another application (application_id {}, {} schema objects), "
                    "not a tocdlab database (application_id {}); it was left untouched",
                    name, hex(app_id), objects, hex(Database::kApplicationId)));
  }
  if (version > Database::kSchemaVersion)
    throw DatabaseError(
        fmt::format("{} was written by a newer tocdlab (schema version {}; this build {} knows up to {}); "
                    "upgrade tocdlab to use it. The file was left untouched",
                    name, version, tocd::version(), Database::kSchemaVersion));
  return {false, static_cast<int>(version)};
}

std::string configure_read_write(const Connection& c) {
  // WAL: readers and the writer never block each other. synchronous=NORMAL: a commit is
  // durable against a process crash; an OS crash / power loss may undo the last commits
  // (never corrupt). See docs/database.md, "Durability".
  std::string mode;
  {
    Statement s(c, "PRAGMA journal_mode=WAL");  // answers the mode now in force
    if (s.step()) mode = s.col_text(0);
  }
  if (mode != "wal") {
    // SQLite keeps the old mode where WAL is impossible (no shared memory, some network file
    // systems). Recording still works, but readers then block the writer: say so.
    const char* file = sqlite3_db_filename(c.get(), "main");
    logger("db")->warn("'{}': journal mode is '{}', not WAL; readers will briefly block recording",
                       file ? file : "", mode);
  }
  c.exec("PRAGMA synchronous=NORMAL; PRAGMA foreign_keys=ON;");
  return mode;
}

int migrate(const Connection& c) {
  Transaction t(c);  // BEGIN IMMEDIATE: two processes opening a new file migrate one at a time
  const auto app_id = c.query_int("PRAGMA application_id");
  const int found = static_cast<int>(c.query_int("PRAGMA user_version"));
  if (app_id != 0 && app_id != Database::kApplicationId)
    throw DatabaseError("not a tocdlab database (application_id " + hex(app_id) + ")");
  if (found > Database::kSchemaVersion)
    throw DatabaseError(fmt::format("written by a newer tocdlab (schema version {})", found));
  for (int v = found; v < Database::kSchemaVersion; ++v) c.exec(kMigrations[static_cast<std::size_t>(v)]);
  if (found < Database::kSchemaVersion) {
    c.exec(fmt::format("PRAGMA application_id = {}; PRAGMA user_version = {};", Database::kApplicationId,
                       Database::kSchemaVersion));
    Statement meta(c, "INSERT OR REPLACE INTO meta(key, value) VALUES(?, ?)");
    const auto put = [&](std::string_view k, std::string_view v) {
      meta.bind(1, k).bind(2, v).run();
      meta.reset();
    };
    put("application", "tocdlab");
    put("schema_version", std::to_string(Database::kSchemaVersion));
    put("migrated_by_version", tocd::version());
    put("migrated_utc", format_utc(wall_clock_ns()));
    if (found == 0) put("created_utc", format_utc(wall_clock_ns()));
  }
  t.commit();
  return found;
}

Connection open_read_only(const std::filesystem::path& path, std::string* note) {
  if (!std::filesystem::exists(path)) throw DatabaseError("no database at '" + path.string() + "'");
  const FileIdentity id = identify(path);
  if (id.is_new) throw DatabaseError("'" + path.string() + "' is an empty file, not a tocdlab database");
  if (id.schema_version < Database::kSchemaVersion)
    throw DatabaseError(
        fmt::format("'{}' has schema version {} (current {}): open it once read-write with this tocdlab "
                    "to upgrade it",
                    path.string(), id.schema_version, Database::kSchemaVersion));
  std::string opened;
  Connection c = open_existing_read_only(path, opened);
  if (note) *note = opened;
  return c;
}

}  // namespace tocd::db::detail

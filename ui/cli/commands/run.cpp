// `tocdlab run`: runs an experiment protocol on the lab's instruments (or the simulated lab)
// and records it into a measurement database (docs/acquisition.md).
#include <algorithm>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "db_location_option.hpp"
#include "numeric_options.hpp"
#include "output_naming.hpp"
#include "output_paths.hpp"
#include "progress.hpp"
#include "run_progress.hpp"
#include "sample_option.hpp"
#include "tocd/acquisition/compare_table.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/acquisition/lab_session.hpp"
#include "tocd/acquisition/protocol.hpp"
#include "tocd/analysis/sim_step_predictor.hpp"
#include "tocd/core/log.hpp"
#include "tocd/core/text_file.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/location.hpp"
#include "tocd/db/push.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/devices/lab.hpp"
#include "tocd/mocks/default_sample.hpp"
#include "tocd/mocks/simulated_lab.hpp"
#include "tocd/mocks/tissue.hpp"

namespace cli = tocd::cli;

namespace {

struct RunOptions {
  std::string protocol, lab, db, operator_name, push_to;
  std::optional<std::int64_t> resume;
  bool simulated = false, no_predict = false, json = false;
  cli::SampleChoice sample;  // --simulated: the simulated lab's sample
  double clock_factor = 1.0;
  std::uint64_t photons = 100000, seed = 1;
};

std::string read_text(const std::string& path) {
  auto text = tocd::read_text_file(path);
  if (!text) throw tocd::ConfigError(fmt::format("cannot read lab config '{}'", path));
  return std::move(*text);
}

namespace acq = tocd::acquisition;
namespace an = tocd::analysis;

// Store-and-forward: the run is whole in its local file; a server that is away now gets it
// from a later push, so a failed push is said and the run's outcome stands.
void push_after_run(const RunOptions& o, const std::string& server, std::int64_t run_id) {
  namespace db = tocd::db;
  if (db::is_server_uri(o.db)) return;  // recorded into the server directly
  const std::string later =
      fmt::format("tocdlab db push --from {} --to {}", o.db, db::display_location(server));
  try {
    for (const auto& r : db::push_runs(o.db, server))
      if (r.local_id == run_id)
        std::cerr << fmt::format("run {} pushed to {} as run {} ({})\n", run_id, db::display_location(server),
                                 r.server_id, db::to_string(r.action));
  } catch (const tocd::Error& e) {
    std::cerr << fmt::format(
        "warning: run {} is recorded in {} but was not pushed: {}. Push it later with: {}\n", run_id, o.db,
        e.what(), later);
  }
}

/// Combinations of options that cannot work: usage errors, before anything is opened.
void check_options(const RunOptions& o) {
  if (o.lab.empty() == !o.simulated)
    throw tocd::ConfigError("give exactly one of --lab LAB.toml or --simulated");
  if (!o.resume && o.protocol.empty()) throw tocd::ConfigError("give a PROTOCOL.toml (or --resume RUN_ID)");
  if (o.clock_factor != 1.0 && !o.simulated) {
    throw tocd::ConfigError("--clock-factor only applies to the simulated lab (--simulated)");
  }
  if (o.simulated) {
    cli::sample_truth(o.sample);  // a bad combination is a usage error, before anything is opened
  } else if (const char* given = cli::first_truth_option(o.sample)) {
    throw CLI::ValidationError(given, "the sample's truth only applies to the simulated lab (--simulated)");
  }
  if (o.resume && !o.protocol.empty()) {
    std::cerr << "note: --resume continues with the protocol stored in run " << *o.resume << "; "
              << o.protocol << " is not read\n";
  }
}

/// Everything the user wrote, parsed before the database is touched.
struct RunInputs {
  std::optional<tocd::devices::LabConfig> lab;
  std::string lab_text;
  std::optional<acq::Protocol> fresh;  ///< the protocol of a new run (none on --resume)
  std::optional<an::SimPredictorSettings> predict;
};

RunInputs parse_inputs(const RunOptions& o) {
  RunInputs in;
  if (!o.lab.empty()) {
    in.lab = tocd::devices::load_lab_config(o.lab);
    in.lab_text = read_text(o.lab);
  }
  if (!o.resume) in.fresh = acq::load_protocol(o.protocol);
  // A run must never record steps it cannot predict: the settings are checked before
  // anything is opened (a vacuum protocol, which is not predicted, is checked as well).
  if (!o.no_predict) {
    in.predict.emplace();
    in.predict->photons = o.photons;
    in.predict->seed = o.seed;
    an::validate(*in.predict);
  }
  if (o.simulated && in.fresh) acq::check_simulated_clock_factor(*in.fresh, o.clock_factor);
  return in;
}

/// Starts the simulated lab for `protocol` and points `in` at it.
std::unique_ptr<tocd::mocks::SimulatedLab> start_simulated_lab(const RunOptions& o,
                                                               const acq::Protocol& protocol, RunInputs& in) {
  tocd::mocks::SimulatedLabOptions so = cli::simulated_lab_options(o.sample);
  so.clock_factor = o.clock_factor;
  so.contact_position_mm = protocol.contact_position_mm;
  so.tissue = cli::prepare_sample(o.sample, protocol);
  // As `tocdlab demo` sets up the lab, so the same protocol and seed measure the same.
  so.source_power_W = protocol.baseline.power_W.value_or(so.source_power_W);
  so.seed = o.seed;
  so.with_vacuum = protocol.kind == acq::StepKind::vacuum;
  auto sim = std::make_unique<tocd::mocks::SimulatedLab>(so);
  in.lab = sim->config();
  in.lab_text = "# simulated lab (tocdlab run --simulated)\n" + tocd::devices::to_toml(*in.lab);
  return sim;
}

/// How a run ended, as the engine says.
struct RunOutcome {
  acq::EngineState final_state = acq::EngineState::idle;
  std::int64_t run_id = 0;
  std::string error;
  acq::EngineStats stats;
};

/// Records the run (new, or resumed) on the lab of `in` until it ends or pauses.
RunOutcome record(const RunOptions& o, tocd::db::Database& db, const acq::Protocol& protocol,
                  const RunInputs& in, tocd::cli::AbortOnSignal& signals, const cli::PhaseTimer& phases) {
  acq::LabSessionOptions session;
  acq::EngineOptions& eo = session.engine;
  eo.clock_factor = o.clock_factor;
  eo.operator_name = o.operator_name;
  eo.lab_config_text = in.lab_text;
  eo.unattended = true;  // nobody can resume a pause from here: a fault ends the run, resumable
  if (in.predict && protocol.kind != acq::StepKind::vacuum)
    session.predictor = an::make_recording_predictor(*in.predict);
  tocd::cli::TerminalProgress progress;
  RunOutcome out;
  acq::LabSession lab_session(db, *in.lab, session, &progress);
  phases.mark("instruments opened");
  acq::Engine& engine = lab_session.engine();
  const tocd::cli::AbortOnSignal::Attached attached(signals, engine);
  out.run_id = o.resume ? engine.resume(*o.resume) : engine.start(protocol);
  cli::say_recording_into(out.run_id, protocol.steps.size(), tocd::db::display_location(o.db));
  phases.mark("run started");
  out.final_state = engine.wait();
  out.error = engine.error();
  out.stats = engine.stats();
  phases.mark("run ended");
  return out;
}

/// The table (or with --json the run summary) on stdout.
void print_result(const RunOptions& o, const RunOutcome& r) {
  const acq::CompareTable table = acq::compare_table(tocd::db::Reader(o.db), r.run_id);
  if (!o.json) {
    std::cout << acq::format_compare_table(table);
    return;
  }
  const acq::EngineStats& stats = r.stats;
  cli::print_json({{"run_id", r.run_id},
                   {"state", acq::to_string(r.final_state)},
                   {"error", r.error},
                   {"samples_lost", stats.samples_dropped + stats.writer.failed_samples},
                   {"predictions",
                    {{"asked", stats.predictions_asked},
                     {"stored", stats.predictions_stored},
                     {"failed", stats.predictions_failed},
                     {"cancelled", stats.predictions_cancelled}}},
                   {"files", {{"database", tocd::db::display_location(o.db)}}},
                   {"compare", acq::to_json(table)}});
}

/// How the run ended, on stderr; throws (exit 1) unless it completed or the operator aborted
/// it, every sample reached the file and no prediction failed (docs/acquisition.md).
void report_end(const RunOptions& o, const RunOutcome& r) {
  const acq::EngineStats& stats = r.stats;
  const std::int64_t run_id = r.run_id;
  const std::string again =
      fmt::format("tocdlab run --resume {} --db {} {}", run_id, tocd::db::display_location(o.db),
                  o.simulated ? std::string("--simulated") : "--lab " + o.lab);
  const std::uint64_t lost = stats.samples_dropped + stats.writer.failed_samples;
  const std::string lost_text =
      lost == 0 ? std::string()
                : fmt::format(
                      "{} sample(s) were lost and are not in {} ({} refused by the full write queue, {} "
                      "lost to failed database commits{})",
                      lost, o.db, stats.samples_dropped, stats.writer.failed_samples,
                      stats.writer.last_error.empty() ? "" : ": " + stats.writer.last_error);
  switch (r.final_state) {
    case acq::EngineState::completed:
      std::cerr << fmt::format("run {} completed\n", run_id);
      break;
    case acq::EngineState::aborted:
      std::cerr << fmt::format("run {} aborted; {}. Continue it with: {}\n", run_id,
                               lost == 0 ? "all data kept" : "data kept as far as stored", again);
      break;
    default:
      throw tocd::Error(fmt::format("run {} {}: {}{}. Continue it with: {}", run_id,
                                    acq::to_string(r.final_state), r.error, lost == 0 ? "" : "; " + lost_text,
                                    again));
  }
  if (lost > 0) throw tocd::Error(fmt::format("run {}: {}", run_id, lost_text));
  // The recording is whole; the predictions are what the run promised beside it.
  if (stats.predictions_cancelled > 0) {
    std::cerr << fmt::format(
        "run {}: {} of {} step prediction(s) cancelled by the abort (tocdlab compare shows which)\n", run_id,
        stats.predictions_cancelled, stats.predictions_asked);
  }
  if (stats.predictions_failed > 0) {
    throw tocd::Error(fmt::format(
        "run {}: the recording is complete, but {} of {} step prediction(s) failed; the events say why "
        "(tocdlab export --db {} --run {} --table events)",
        run_id, stats.predictions_failed, stats.predictions_asked, o.db, run_id));
  }
}

void run_protocol(const RunOptions& o) {
  check_options(o);
  RunInputs in = parse_inputs(o);
  // Before any thread starts (simulated lab servers, drivers, engine): every thread then
  // inherits the blocked SIGINT/SIGTERM and only the watcher sees them.
  tocd::cli::AbortOnSignal signals(std::cerr);
  const cli::PhaseTimer phases(*tocd::logger("cli"), "run");
  tocd::db::Database db(o.db);
  const acq::Protocol protocol = in.fresh ? *in.fresh
                                          : acq::parse_protocol(db.run(*o.resume).protocol_text,
                                                                fmt::format("run {} protocol", *o.resume));
  if (o.simulated && !in.fresh) acq::check_simulated_clock_factor(protocol, o.clock_factor);
  std::unique_ptr<tocd::mocks::SimulatedLab> sim;
  if (o.simulated) sim = start_simulated_lab(o, protocol, in);
  const RunOutcome outcome = record(o, db, protocol, in, signals, phases);
  print_result(o, outcome);
  const std::string push_to = o.push_to.empty() && in.lab ? in.lab->push_to : o.push_to;
  if (!push_to.empty()) push_after_run(o, push_to, outcome.run_id);  // however it ended: interrupted too
  report_end(o, outcome);
}

void install_run(CLI::App& root) {
  auto* cmd =
      root.add_subcommand("run", "Run an experiment protocol and record it (see docs/acquisition.md)");
  auto o = std::make_shared<RunOptions>();
  cmd->add_option("protocol", o->protocol, "experiment protocol TOML (not needed with --resume)");
  cmd->add_option("--lab", o->lab, "lab config TOML: which instruments, where");
  cmd->add_flag("--simulated", o->simulated, "use the built-in simulated lab instead of --lab");
  cli::add_sample_options(*cmd, o->sample);
  cmd->add_option("--db", o->db,
                  "measurement database file (created when absent), or a PostgreSQL server "
                  "(postgresql://...)")
      ->check(cli::database_output())
      ->required();
  cmd->add_option("--resume", o->resume, "continue the interrupted or aborted run with this id")
      ->check(cli::whole_in(std::int64_t{1}, std::numeric_limits<std::int64_t>::max()));
  cmd->add_option("--clock-factor", o->clock_factor, "simulated seconds per real second (--simulated only)")
      ->check(cli::real_above(0.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--operator", o->operator_name, "operator name stored with the run");
  cmd->add_option("--push-to", o->push_to,
                  "after the run, push it from the --db file to this PostgreSQL server (postgresql://...; "
                  "overrides the lab config's [lab] push_to)")
      ->check(CLI::Validator(
          [](std::string& v) {
            return tocd::db::is_server_uri(v) ? std::string() : "not a postgresql:// URI: " + v;
          },
          "URI"));
  cli::add_photons_option(*cmd, "--photons", o->photons,
                          "Monte Carlo photons per predicted step (FE + mesh + MC per step)");
  cli::add_seed_option(*cmd, o->seed, "random seed of the predictions (and of the simulated lab's noise)");
  cmd->add_flag("--no-predict", o->no_predict, "record only; no simulator prediction per step");
  cmd->add_flag(
      "--json", o->json,
      "print the run summary (per-step measured vs. predicted, files written) as one JSON document");
  cmd->callback([o] { run_protocol(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(run, install_run);

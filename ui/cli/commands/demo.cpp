// `tocdlab demo`: the main job end to end on the simulated lab — a pin-compression protocol on
// simulated instruments (real wire protocols), recorded into a measurement database, every
// step predicted by the FE + Monte Carlo simulator, measured vs. predicted printed and written
// as CSV. The simulated sample deliberately differs from the model's default tissue (stiffer,
// strain-graded optics) so that the comparison is not circular. Below the table, what the
// recorded run says about the sample (tocdlab identify, docs/identify.md).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "db_location_option.hpp"
#include "identify_report.hpp"
#include "numeric_options.hpp"
#include "output_naming.hpp"
#include "output_paths.hpp"
#include "progress.hpp"
#include "run_progress.hpp"
#include "sample_option.hpp"
#include "tocd/acquisition/compare_table.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/acquisition/hold_clearing.hpp"
#include "tocd/acquisition/lab_session.hpp"
#include "tocd/acquisition/protocol.hpp"
#include "tocd/analysis/identify_sample.hpp"
#include "tocd/analysis/sim_step_predictor.hpp"
#include "tocd/core/atomic_file.hpp"
#include "tocd/core/error.hpp"
#include "tocd/core/log.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/location.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/devices/lab.hpp"
#include "tocd/mocks/default_sample.hpp"
#include "tocd/mocks/sim_tissue.hpp"
#include "tocd/mocks/sim_tissue_cache.hpp"
#include "tocd/mocks/simulated_lab.hpp"
#include "truth_check.hpp"

namespace cli = tocd::cli;

namespace {

struct DemoOptions {
  std::string db = "tocdlab-demo.db";
  std::string csv;  // -o/--output; default: next to the database
  std::string protocol;
  std::string cache_dir = tocd::mocks::default_sim_tissue_cache_dir().string();
  bool no_cache = false;
  std::uint64_t photons = 100000;
  std::uint64_t sample_photons = tocd::mocks::kDefaultSamplePhotons;
  std::uint64_t seed = 1;
  int threads = 0;
  double clock_factor = 2.0;
  cli::SampleChoice truth;  // --truth-* (and --delayed-clearing)
  bool json = false;
  std::uint64_t identify_photons = 50000;  // the identification's Monte Carlo, per held step
  bool no_identify = false;
};

// The identified sample of the recorded run (docs/identify.md), or nothing when it is not
// asked for or fails. A failure is reported on stderr and does not change the demo's exit
// status: the run itself was recorded and predicted, which is what the demo's status says.
std::optional<tocd::analysis::SampleIdentification> identify_run(const DemoOptions& o,
                                                                 const tocd::db::Reader& reader,
                                                                 std::int64_t run_id) {
  if (o.no_identify) return std::nullopt;
  tocd::analysis::SampleIdentificationOptions so;
  so.monte_carlo.photons = o.identify_photons;
  so.monte_carlo.threads = o.threads;
  if (!cli::progress_quiet())
    so.progress = [](const std::string& line) { std::cerr << "identify: " << line << std::endl; };
  try {
    return tocd::analysis::identify_sample(reader, run_id, so);
  } catch (const tocd::Error& e) {
    std::cerr << fmt::format("tocdlab demo: identifying the sample of run {} failed: {}", run_id, e.what())
              << std::endl;
    return std::nullopt;
  }
}

namespace acq = tocd::acquisition;
namespace an = tocd::analysis;

/// The prediction settings, checked before the sample's preparation (a minute or more).
an::SimPredictorSettings predictor_settings(const DemoOptions& o) {
  an::SimPredictorSettings predict;
  predict.photons = o.photons;
  predict.seed = o.seed;
  predict.threads = o.threads;
  an::validate(predict);
  return predict;
}

/// The simulated sample: FE load curve and Monte Carlo transmission at the protocol's steps.
struct DemoSample {
  tocd::mocks::SampleTruth truth;
  tocd::mocks::SimTissueTable table;
  std::shared_ptr<tocd::mocks::TissueModel> tissue;
};

DemoSample prepare_demo_sample(const DemoOptions& o, const acq::Protocol& protocol) {
  cli::SampleChoice sample = o.truth;
  DemoSample out;
  out.truth = cli::sample_truth(sample);  // a usage error before any work
  sample.photons = o.sample_photons;
  sample.threads = o.threads;
  sample.cache_dir = o.cache_dir;
  sample.no_cache = o.no_cache;
  out.tissue = cli::prepare_sample(sample, protocol, &out.table);
  return out;
}

/// The simulated lab on loopback TCP / a pty, holding the demo's sample.
tocd::mocks::SimulatedLabOptions demo_lab_options(const DemoOptions& o, const acq::Protocol& protocol,
                                                  const DemoSample& sample) {
  tocd::mocks::SimulatedLabOptions so = tocd::mocks::simulated_lab_options(sample.truth);
  so.tissue = sample.tissue;
  so.clock_factor = o.clock_factor;
  so.contact_position_mm = protocol.contact_position_mm;
  so.source_power_W = protocol.baseline.power_W.value_or(1e-3);
  so.with_vacuum = false;
  so.seed = o.seed;
  return so;
}

struct DemoRun {
  acq::EngineState final_state = acq::EngineState::idle;
  std::int64_t run_id = 0;
  std::string error;
};

/// Records and predicts the protocol on the lab of `lab_cfg`, the instruments through the
/// real drivers, each step predicted by the published skin at the sample's thickness.
DemoRun record_demo(const DemoOptions& o, const acq::Protocol& protocol,
                    const tocd::devices::LabConfig& lab_cfg, const an::SimPredictorSettings& predict,
                    tocd::cli::AbortOnSignal& signals, const cli::PhaseTimer& phases) {
  acq::LabSessionOptions session;
  session.predictor = an::make_recording_predictor(predict);
  tocd::db::Database db(o.db);
  acq::EngineOptions& eo = session.engine;
  eo.clock_factor = o.clock_factor;
  eo.operator_name = "tocdlab demo";
  eo.unattended = true;  // a fault ends the demo run (interrupted) rather than pausing it for good
  eo.lab_config_text = "# simulated lab (tocdlab demo)\n" + tocd::devices::to_toml(lab_cfg);
  tocd::cli::TerminalProgress progress;
  DemoRun out;
  acq::LabSession lab_session(db, lab_cfg, session, &progress);
  acq::Engine& engine = lab_session.engine();
  const tocd::cli::AbortOnSignal::Attached attached(signals, engine);
  out.run_id = engine.start(protocol);
  cli::say_recording_into(out.run_id, protocol.steps.size(), tocd::db::display_location(o.db));
  phases.mark("run started");
  out.final_state = engine.wait();
  out.error = engine.error();
  phases.mark("run recorded and predicted");
  return out;
}

/// Measured vs. predicted: the table (or with --json the whole run summary) on stdout, with
/// the clearing during the holds and what the run says about its sample.
void print_demo(const DemoOptions& o, const DemoRun& run, const DemoSample& sample,
                const tocd::db::Reader& reader, const acq::CompareTable& t,
                const std::vector<acq::HoldClearing>& holds, const std::string& csv_path) {
  // The identification needs a whole run: an interrupted one fails below without it.
  const bool identify = run.final_state == acq::EngineState::completed;
  if (o.json) {
    const auto id = identify ? identify_run(o, reader, run.run_id) : std::nullopt;
    nlohmann::json summary = {{"run_id", run.run_id},
                              {"state", acq::to_string(run.final_state)},
                              {"error", run.error},
                              {"files", {{"database", tocd::db::display_location(o.db)}, {"csv", csv_path}}},
                              {"simulated_sample",
                               {{"seconds", sample.table.seconds},
                                {"from_cache", sample.table.from_cache},
                                {"cache_file", sample.table.cache_file},
                                {"truth", tocd::mocks::to_json(sample.truth)}}},
                              {"compare", acq::to_json(t)},
                              {"hold_clearing", acq::hold_clearing_json(holds)}};
    if (id) {
      summary["identified"] = tocd::analysis::to_json(*id);
      summary["truth_check"] = cli::to_json(cli::check_against_truth(*id, sample.truth, sample.table));
    }
    cli::print_json(summary);
    return;
  }
  std::cout << acq::format_compare_table(t);
  std::cout
      << "T = transmitted power / glass-only baseline power; predicted T from the FE + Monte Carlo model "
         "(published Ogden skin, threshold optics) +- its Monte Carlo standard error.\n";
  std::cout << "\nClearing during the holds: measured T over the first and the last second of each "
               "step's recording (the sample keeps clearing while its water drains):\n"
            << acq::format_hold_clearing(holds);
  // The table first: the identification takes a minute or more (its Monte Carlo).
  std::cout << std::flush;
  if (const auto id = identify ? identify_run(o, reader, run.run_id) : std::nullopt) {
    std::cout << '\n';
    tocd::cli::print_identification(std::cout, *id);
    std::cout << '\n';
    cli::print_truth_check(std::cout, cli::check_against_truth(*id, sample.truth, sample.table));
  }
}

/// The demo fails unless its run completed with every step measured and predicted.
void check_demo_end(const DemoRun& run, const acq::CompareTable& t) {
  if (run.final_state != acq::EngineState::completed)
    throw tocd::Error(
        fmt::format("demo run {} ended {}: {}", run.run_id, acq::to_string(run.final_state), run.error));
  std::size_t missing = 0;
  for (const auto& l : t.lines)
    if (!l.completed || !l.has_prediction) ++missing;
  if (missing > 0)
    throw tocd::Error(
        fmt::format("demo run {}: {} step(s) without a measured and predicted T", run.run_id, missing));
}

void run_demo(const DemoOptions& o) {
  const acq::Protocol protocol = o.protocol.empty() ? acq::demo_protocol() : acq::load_protocol(o.protocol);
  if (protocol.kind == acq::StepKind::vacuum)
    throw tocd::ConfigError("tocdlab demo runs pin-compression protocols");
  acq::check_simulated_clock_factor(protocol, o.clock_factor);
  const an::SimPredictorSettings predict = predictor_settings(o);
  // Beside a database file; a server's table goes to the working directory.
  const std::string csv_path = !o.csv.empty() ? o.csv
                               : tocd::db::is_server_uri(o.db)
                                   ? std::string("tocdlab-demo.csv")
                                   : std::filesystem::path(o.db).replace_extension(".csv").string();

  const DemoSample sample = prepare_demo_sample(o, protocol);
  const auto log = tocd::logger("cli");
  const cli::PhaseTimer phases(*log, "demo");
  log->debug("demo: phase 'simulated sample' took {:.3f} s ({})", sample.table.seconds,
             sample.table.from_cache ? "from cache " + sample.table.cache_file : "computed");

  std::optional<tocd::cli::AbortOnSignal> signals;
  signals.emplace(std::cerr);
  tocd::mocks::SimulatedLab lab(demo_lab_options(o, protocol, sample));
  phases.mark("simulated lab started");
  const tocd::devices::LabConfig lab_cfg = lab.config();
  const DemoRun run = record_demo(o, protocol, lab_cfg, predict, *signals, phases);
  // No pin moves any more: SIGINT and SIGTERM end the program again at once (the
  // identification below runs for minutes and would otherwise not hear them).
  signals.reset();

  const tocd::db::Reader reader(o.db);
  const acq::CompareTable t = acq::compare_table(reader, run.run_id);
  // Clearing over time: T at the start and the end of each step's recording window.
  const auto holds = acq::hold_clearing(reader, run.run_id);
  tocd::write_file_atomically(csv_path, cli::to_naming_table_csv(acq::format_compare_csv(t)));
  phases.mark("compare table written");
  print_demo(o, run, sample, reader, t, holds, csv_path);
  cli::announce_file("database",
                     fmt::format("{}  (tocdlab compare --db {} --run {})", tocd::db::display_location(o.db),
                                 tocd::db::display_location(o.db), run.run_id));
  cli::announce_file("table (CSV)", csv_path);
  check_demo_end(run, t);
}

void install_demo(CLI::App& root) {
  auto* cmd = root.add_subcommand(
      "demo", "Run the demo pin-compression protocol on the simulated lab and compare with the simulator");
  auto o = std::make_shared<DemoOptions>();
  cmd->add_option(
         "--db", o->db,
         "measurement database file (created when absent; runs are appended), or a PostgreSQL server "
         "(postgresql://...)")
      ->check(cli::database_output())
      ->capture_default_str();
  cmd->add_option("-o,--output", o->csv,
                  "measured vs. predicted table as CSV (default: the database name with .csv)")
      ->check(cli::output_file());
  cmd->add_option("--csv", o->csv, "deprecated: use -o FILE.csv")->check(cli::output_file())->group("");
  cli::add_photons_option(*cmd, "--photons", o->photons, "Monte Carlo photons per predicted step");
  cli::add_photons_option(*cmd, "--sample-photons", o->sample_photons,
                          "Monte Carlo photons per point of the simulated sample's transmission curve");
  cli::add_seed_option(
      *cmd, o->seed,
      "random seed (predictions and instrument noise; the identification keeps tocdlab identify's seed, 11)");
  cli::add_threads_option(*cmd, o->threads, "Monte Carlo threads (0 = all cores)");
  cmd->add_option("--clock-factor", o->clock_factor, "simulated seconds per real second")
      ->check(cli::real_above(0.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--protocol", o->protocol,
                  "another pin-compression protocol TOML instead of the built-in one");
  cmd->add_flag(
      "--json", o->json,
      "print the run summary (per-step measured vs. predicted, files written) as one JSON document");
  cmd->add_option("--cache-dir", o->cache_dir,
                  "where the simulated sample's prepared tables are cached ($TOCDLAB_CACHE_DIR, else "
                  "$XDG_CACHE_HOME/tocdlab, else ~/.cache/tocdlab)")
      ->capture_default_str();
  cmd->add_flag("--no-cache", o->no_cache, "prepare the simulated sample afresh and do not cache it");
  cmd->add_option("--identify-photons", o->identify_photons,
                  "Monte Carlo photons per held step for identifying the sample's clearing optics")
      ->check(cli::whole_in(std::uint64_t{1000}, std::uint64_t{1000000000}))
      ->capture_default_str();
  cmd->add_flag("--no-identify", o->no_identify,
                "do not identify the sample from the recorded run (tocdlab identify)");
  cli::add_truth_options(*cmd, o->truth, true);
  cmd->callback([o] { run_demo(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(demo, install_demo);

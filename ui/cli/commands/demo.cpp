// `tocdlab demo`: the main job end to end on the simulated lab — a pin-compression protocol on
// simulated instruments (real wire protocols), recorded into a measurement database, every
// step predicted by the FE + Monte Carlo simulator, measured vs. predicted printed and written
// as CSV. The simulated sample deliberately differs from the model's default tissue (stiffer,
// strain-graded optics) so that the comparison is not circular.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <unistd.h>

#include "command_registry.hpp"
#include "numeric_options.hpp"
#include "run_progress.hpp"
#include "tocd/acquisition/compare_table.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/acquisition/lab_session.hpp"
#include "tocd/acquisition/protocol.hpp"
#include "tocd/acquisition/sim_step_predictor.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/devices/lab.hpp"
#include "tocd/mocks/sim_tissue.hpp"
#include "tocd/mocks/simulated_lab.hpp"

namespace cli = tocd::cli;

namespace {

struct DemoOptions {
  std::string db = "tocdlab-demo.db";
  std::string csv;  // default: next to the database
  std::string protocol;
  std::uint64_t photons = 100000;
  std::uint64_t sample_photons = 50000;
  std::uint64_t seed = 1;
  int threads = 0;
  double clock_factor = 2.0;
  bool json = false;
};

void run_demo(const DemoOptions& o) {
  namespace acq = tocd::acquisition;
  const acq::Protocol protocol = o.protocol.empty() ? acq::demo_protocol() : acq::load_protocol(o.protocol);
  if (protocol.kind == acq::StepKind::vacuum)
    throw tocd::ConfigError("tocdlab demo runs pin-compression protocols");
  const std::string csv_path =
      o.csv.empty() ? std::filesystem::path(o.db).replace_extension(".csv").string() : o.csv;

  // 1. The simulated sample: FE load curve and Monte Carlo transmission at the protocol's steps.
  tocd::mocks::SimTissueSpec spec;
  spec.thickness_mm = protocol.sample.thickness_mm;
  spec.displacements_mm.clear();
  for (const auto& s : protocol.steps)
    if (s.displacement_mm > 0) spec.displacements_mm.push_back(s.displacement_mm);
  spec.photons = o.sample_photons;
  spec.threads = o.threads;
  spec.progress = [](const std::string& line) { std::cout << line << std::endl; };
  tocd::mocks::SimTissueTable table;
  auto tissue = tocd::mocks::make_simulated_tissue(spec, &table);
  std::cout << fmt::format("simulated sample ready ({:.1f} s)\n", table.seconds);

  // 2. The simulated lab on loopback TCP / a pty, and the instruments through the real drivers.
  tocd::cli::AbortOnSignal signals(std::cerr);
  tocd::mocks::SimulatedLabOptions so;
  so.tissue = tissue;
  so.clock_factor = o.clock_factor;
  so.contact_position_mm = protocol.contact_position_mm;
  so.source_power_W = protocol.baseline.power_W.value_or(1e-3);
  so.with_vacuum = false;
  so.seed = o.seed;
  tocd::mocks::SimulatedLab lab(so);
  const tocd::devices::LabConfig lab_cfg = lab.config();

  // 3. The model that predicts each step: the published skin at the sample's thickness.
  acq::LabSessionOptions session;
  session.predict = acq::SimPredictorSettings{};
  session.predict->photons = o.photons;
  session.predict->seed = o.seed;
  session.predict->mc_threads = o.threads;

  tocd::db::Database db(o.db);
  acq::EngineOptions& eo = session.engine;
  eo.clock_factor = o.clock_factor;
  eo.operator_name = "tocdlab demo";
  eo.unattended = true;  // a fault ends the demo run (interrupted) rather than pausing it for good
  eo.lab_config_text = "# simulated lab (tocdlab demo)\n" + tocd::devices::to_toml(lab_cfg);
  tocd::cli::TerminalProgress progress(std::cout, ::isatty(STDOUT_FILENO) != 0);
  acq::EngineState final_state;
  std::int64_t run_id = 0;
  std::string error;
  {
    acq::LabSession lab_session(db, lab_cfg, session, &progress);
    acq::Engine& engine = lab_session.engine();
    const tocd::cli::AbortOnSignal::Attached attached(signals, engine);
    run_id = engine.start(protocol);
    std::cout << fmt::format("run {} ({} steps) recording into {}", run_id, protocol.steps.size(), o.db)
              << std::endl;
    final_state = engine.wait();
    error = engine.error();
  }

  // 4. Measured vs. predicted, on the terminal and as CSV.
  const acq::CompareTable t = acq::compare_table(tocd::db::Reader(o.db), run_id);
  {
    std::ofstream csv(csv_path);
    if (!csv) throw tocd::Error(fmt::format("cannot write '{}'", csv_path));
    csv << acq::format_compare_csv(t);
  }
  if (o.json) {
    std::cout << acq::to_json(t).dump(2) << '\n';
  } else {
    std::cout << '\n' << acq::format_compare_table(t);
    std::cout
        << "T = transmitted power / glass-only baseline power; predicted T from the FE + Monte Carlo model "
           "(published Ogden skin, threshold optics) +- its Monte Carlo standard error.\n";
  }
  std::cout << fmt::format("database: {}  (tocdlab compare --db {} --run {})\ncsv: {}\n", o.db, o.db, run_id,
                           csv_path);
  if (final_state != acq::EngineState::completed)
    throw tocd::Error(fmt::format("demo run {} ended {}: {}", run_id, acq::to_string(final_state), error));
  std::size_t missing = 0;
  for (const auto& l : t.lines)
    if (!l.completed || !l.has_prediction) ++missing;
  if (missing > 0)
    throw tocd::Error(
        fmt::format("demo run {}: {} step(s) without a measured and predicted T", run_id, missing));
}

void install_demo(CLI::App& root) {
  auto* cmd = root.add_subcommand(
      "demo", "Run the demo pin-compression protocol on the simulated lab and compare with the simulator");
  auto o = std::make_shared<DemoOptions>();
  cmd->add_option("--db", o->db, "measurement database file (created when absent; runs are appended)")
      ->capture_default_str();
  cmd->add_option("--csv", o->csv,
                  "measured vs. predicted table as CSV (default: the database name with .csv)");
  cmd->add_option("--photons", o->photons, "Monte Carlo photons per predicted step")
      ->check(cli::whole_in(std::uint64_t{1}, cli::kMaxPhotons))
      ->capture_default_str();
  cmd->add_option("--sample-photons", o->sample_photons,
                  "Monte Carlo photons per point of the simulated sample's transmission curve")
      ->check(cli::whole_in(std::uint64_t{1}, cli::kMaxPhotons))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "random seed (predictions and instrument noise)")
      ->check(cli::whole_in(std::uint64_t{0}, std::numeric_limits<std::uint64_t>::max()))
      ->capture_default_str();
  cmd->add_option("--threads", o->threads, "Monte Carlo threads (0 = all cores)")
      ->check(cli::whole_in(std::int64_t{0}, std::int64_t{cli::kMaxThreads}))
      ->capture_default_str();
  cmd->add_option("--clock-factor", o->clock_factor, "simulated seconds per real second")
      ->check(cli::real_above(0.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--protocol", o->protocol,
                  "another pin-compression protocol TOML instead of the built-in one");
  cmd->add_flag("--json", o->json, "print the compare table as JSON");
  cmd->callback([o] { run_demo(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(demo, install_demo);

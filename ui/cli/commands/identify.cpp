// `tocdlab identify`: what a recorded run says about its sample (docs/identify.md).
#include <iostream>
#include <limits>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "command_registry.hpp"
#include "db_location_option.hpp"
#include "identify_report.hpp"
#include "numeric_options.hpp"
#include "output_naming.hpp"
#include "tocd/analysis/identify_sample.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/reader.hpp"

namespace {

struct IdentifyOptions {
  std::string db;
  std::int64_t run = 0;
  int prony_terms = 1;
  double pin_radius = 1.5;
  bool mechanics_only = false;
  bool no_optics = false;
  std::uint64_t photons = 50000;
  std::uint64_t seed = 11;
  int threads = 0;
  bool json = false;
};

void identify(const IdentifyOptions& o) {
  tocd::analysis::SampleIdentificationOptions so;
  so.mechanics.prony_terms = o.prony_terms;
  so.mechanics.pin_radius_mm = o.pin_radius;
  so.clearing = !o.mechanics_only;
  so.optics = !o.mechanics_only && !o.no_optics;
  so.monte_carlo.photons = o.photons;
  so.monte_carlo.seed = o.seed;
  so.monte_carlo.threads = o.threads;
  so.progress = [](const std::string& line) { std::cerr << line << '\n'; };
  const auto id = tocd::analysis::identify_sample(tocd::db::Reader(o.db), o.run, so);
  if (o.json)
    tocd::cli::print_json(tocd::analysis::to_json(id));
  else
    tocd::cli::print_identification(std::cout, id);
}

void install_identify(CLI::App& root) {
  auto* cmd = root.add_subcommand(
      "identify",
      "Identify a recorded run's sample: QLV mechanics on the FE, clearing optics on the Monte Carlo, "
      "with 95 % intervals and what the run does not determine (docs/identify.md)");
  auto o = std::make_shared<IdentifyOptions>();
  cmd->add_option("--db", o->db, "measurement database file, or a PostgreSQL server (postgresql://...)")
      ->required()
      ->check(tocd::cli::database_input());
  cmd->add_option("--run", o->run, "run id (see tocdlab runs --db FILE)")
      ->required()
      ->check(CLI::Range(std::int64_t{1}, std::numeric_limits<std::int64_t>::max()));
  cmd->add_option("--prony-terms", o->prony_terms, "relaxation terms of the QLV model")
      ->capture_default_str()
      ->check(CLI::Range(1, 3));
  cmd->add_option("--pin-radius", o->pin_radius, "pin radius of the FE (mm)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--photons", o->photons, "Monte Carlo photons per held step and evaluation of the optics")
      ->capture_default_str()
      ->check(CLI::Range(std::uint64_t{1000}, std::uint64_t{1000000000}));
  tocd::cli::add_seed_option(*cmd, o->seed, "random seed of the optics' Monte Carlo");
  tocd::cli::add_threads_option(*cmd, o->threads, "Monte Carlo threads (0: all cores)");
  cmd->add_flag("--mechanics-only", o->mechanics_only, "identify the mechanics alone (no Monte Carlo)");
  cmd->add_flag("--no-optics", o->no_optics,
                "the mechanics and the clearing's time course, not the optics (no Monte Carlo: seconds)");
  cmd->add_flag("--json", o->json, "print the identification as one JSON document");
  cmd->callback([o] { identify(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(identify, install_identify);

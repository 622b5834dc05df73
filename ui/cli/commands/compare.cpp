// `tocdlab compare`: measured vs. predicted transmission of a run, step by step.
#include <iostream>
#include <memory>
#include <string>

#include "command_registry.hpp"
#include "compare_fitted.hpp"
#include "compare_water.hpp"
#include "db_location_option.hpp"
#include "numeric_options.hpp"
#include "output_naming.hpp"
#include "tocd/acquisition/compare_table.hpp"
#include "tocd/db/reader.hpp"

namespace cli = tocd::cli;

namespace {

struct CompareOptions {
  std::string db;
  std::int64_t run = 0;
  bool json = false;
  tocd::cli::CompareFittedOptions fitted;  ///< --material
  std::string optics;                      ///< "water": T(t) through each hold
  tocd::cli::CompareWaterOptions water;
};

void install_compare(CLI::App& root) {
  auto* cmd = root.add_subcommand("compare", "Measured vs. predicted transmission per step of a run");
  auto o = std::make_shared<CompareOptions>();
  cli::add_runs_database(cmd, o->db);
  cli::add_run_id(cmd, o->run);
  cmd->add_flag("--json", o->json, "machine-readable output");
  cmd->add_option(
      "--material", o->fitted.material,
      "also re-predict every step with the sample's own law: 'fitted' (FE fit of this run), "
      "'identified' (the sample identified from this run, optics included: tocdlab identify) or a "
      "`tocdlab fit --method fe --json` file; shows MC and model-uncertainty bands");
  cmd->add_option("--pin-radius", o->fitted.pin_radius, "pin radius [mm] for the fit (--material fitted)")
      ->check(cli::real_above(0.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--photons", o->fitted.photons,
                  "photons per re-prediction (--material; default: as stored) or per time point (--optics "
                  "water; default 20000)")
      ->check(cli::whole_in(std::uint64_t{1}, cli::kMaxPhotons));
  cmd->add_option("--threads", o->fitted.threads, "Monte Carlo threads (0 = all cores)")
      ->check(cli::whole_in(std::int64_t{0}, std::int64_t{cli::kMaxThreads}));
  cmd->add_option(
         "--optics", o->optics,
         "water: T(t) at points in each hold from the biphasic FE driven along the run's recorded pin "
         "displacement, next to the measured power there (docs/water.md)")
      ->check(CLI::IsMember({"water"}));
  auto& wc = o->water.course;
  auto* points = cmd->add_option("--points-per-hold", wc.points_per_hold,
                                 "water optics: time points in each step's recording window")
                     ->check(cli::whole_in(std::int64_t{1}, std::int64_t{100}))
                     ->capture_default_str();
  auto* window = cmd->add_option("--window-s", wc.window_s,
                                 "water optics: measured T averaged over this many seconds around each point")
                     ->check(cli::real_above(0.0, 1e4))
                     ->capture_default_str();
  auto* nu = cmd->add_option("--drained-poisson", wc.drained_poisson,
                             "water optics: drained Poisson's ratio of the skeleton")
                 ->check(cli::real_in(-0.99, 0.4999))
                 ->capture_default_str();
  auto* k0 = cmd->add_option("--k0", wc.k0_mm4_per_Ns,
                             "water optics: permeability at the reference state (mm^4/(N s))")
                 ->check(cli::real_above(0.0, 1e6))
                 ->capture_default_str();
  auto* budget =
      cmd->add_option("--fe-budget-s", wc.fe_budget_s,
                      "water optics: wall seconds the biphasic FE may take; points after are not computed")
          ->check(cli::real_above(0.0, 1e6))
          ->capture_default_str();
  auto* seed = cli::add_seed_option(*cmd, wc.seed, "water optics: Monte Carlo seed");
  auto* mesh = cmd->add_option("--mesh", wc.mesh_preset, "water optics: composite mesh preset")
                   ->check(CLI::IsMember({"fast", "paper"}))
                   ->capture_default_str();
  cmd->callback([o, cmd, points, window, nu, k0, budget, seed, mesh] {
    if (o->optics == "water") {
      // The water course makes its own predictions; the fitted-law options have no meaning here.
      for (const char* other : {"--material", "--pin-radius"})
        if (cmd->count(other) > 0) throw CLI::ValidationError(other, "is not used with --optics water");
      o->water.db = o->db;
      o->water.run = o->run;
      o->water.json = o->json;
      if (cmd->count("--photons") > 0) o->water.course.photons = o->fitted.photons;
      o->water.course.threads = o->fitted.threads;
      tocd::cli::run_compare_water(o->water);
      return;
    }
    for (const CLI::Option* opt : {points, window, nu, k0, budget, seed, mesh})
      if (opt->count() > 0) throw CLI::ValidationError(opt->get_name(), "needs --optics water");
    if (!o->fitted.material.empty()) {
      o->fitted.db = o->db;
      o->fitted.run = o->run;
      o->fitted.json = o->json;
      tocd::cli::run_compare_fitted(o->fitted);
      return;
    }
    const auto table = tocd::acquisition::compare_table(tocd::db::Reader(o->db), o->run);
    if (o->json) {
      cli::print_json(tocd::acquisition::to_json(table));
    } else {
      std::cout << tocd::acquisition::format_compare_table(table);
    }
  });
}

}  // namespace

TOCD_CLI_COMMAND(compare, install_compare);

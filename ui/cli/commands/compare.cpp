// `tocdlab compare`: measured vs. predicted transmission of a run, step by step.
#include <iostream>
#include <limits>
#include <memory>
#include <string>

#include "command_registry.hpp"
#include "compare_fitted.hpp"
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
};

void install_compare(CLI::App& root) {
  auto* cmd = root.add_subcommand("compare", "Measured vs. predicted transmission per step of a run");
  auto o = std::make_shared<CompareOptions>();
  cmd->add_option("--db", o->db, "measurement database file")->required();
  cmd->add_option("--run", o->run, "run id (see tocdlab runs)")
      ->check(cli::whole_in(std::int64_t{1}, std::numeric_limits<std::int64_t>::max()))
      ->required();
  cmd->add_flag("--json", o->json, "machine-readable output");
  cmd->add_option("--material", o->fitted.material,
                  "also re-predict every step with the sample's own law: 'fitted' (FE fit of this run) or a "
                  "`tocdlab fit --method fe --json` file; shows MC and model-uncertainty bands");
  cmd->add_option("--pin-radius", o->fitted.pin_radius, "pin radius [mm] for the fit (--material fitted)")
      ->check(cli::real_above(0.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--photons", o->fitted.photons, "photons per re-prediction (default: as stored)")
      ->check(cli::whole_in(std::uint64_t{1}, cli::kMaxPhotons));
  cmd->add_option("--threads", o->fitted.threads, "Monte Carlo threads (0 = all cores)")
      ->check(cli::whole_in(std::int64_t{0}, std::int64_t{cli::kMaxThreads}));
  cmd->callback([o] {
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

// `tocdlab compare`: measured vs. predicted transmission of a run, step by step.
#include <iostream>
#include <limits>
#include <memory>
#include <string>

#include "command_registry.hpp"
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
};

void install_compare(CLI::App& root) {
  auto* cmd = root.add_subcommand("compare", "Measured vs. predicted transmission per step of a run");
  auto o = std::make_shared<CompareOptions>();
  cmd->add_option("--db", o->db, "measurement database file")->required();
  cmd->add_option("--run", o->run, "run id (see tocdlab runs)")
      ->check(cli::whole_in(std::int64_t{1}, std::numeric_limits<std::int64_t>::max()))
      ->required();
  cmd->add_flag("--json", o->json, "machine-readable output");
  cmd->callback([o] {
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

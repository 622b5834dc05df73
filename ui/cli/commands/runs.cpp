// `tocdlab runs`: lists the runs of a measurement database.
#include <iostream>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "command_registry.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/printable.hpp"
#include "tocd/db/reader.hpp"

namespace {

void list_runs(const std::string& path) {
  const tocd::db::Reader reader(path);
  const auto runs = reader.runs();
  if (runs.empty()) {
    std::cout << "no runs in " << path << '\n';
    return;
  }
  std::cout << fmt::format("{:>4}  {:<12}  {:<24}  {:>5}  {:>11}  {:>6}  {}\n", "id", "status",
                           "started (UTC)", "steps", "predictions", "events", "name");
  for (const auto& s : runs) {
    std::cout << fmt::format(
        "{:>4}  {:<12}  {:<24}  {:>5}  {:>11}  {:>6}  {}\n", s.run.id,
        std::string(tocd::db::to_string(tocd::db::shown_status(s))) + (s.live ? "*" : ""),
        tocd::format_utc(s.run.started_utc_ns), s.steps, s.predictions, s.events,
        tocd::printable_text(s.run.name));  // names come from files: no raw controls
  }
  for (const auto& s : runs) {
    if (s.live) {
      std::cout << "* recording in another process right now\n";
      break;
    }
  }
}

void install_runs(CLI::App& root) {
  auto* cmd = root.add_subcommand("runs", "List the runs of a measurement database");
  auto path = std::make_shared<std::string>();
  cmd->add_option("--db", *path, "measurement database file")->required();
  cmd->callback([path] { list_runs(*path); });
}

}  // namespace

TOCD_CLI_COMMAND(runs, install_runs);

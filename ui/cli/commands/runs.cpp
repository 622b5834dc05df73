// `tocdlab runs`: lists the runs of a measurement database.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "db_location_option.hpp"
#include "output_naming.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/printable.hpp"
#include "tocd/db/location.hpp"
#include "tocd/db/reader.hpp"

namespace {

struct RunsOptions {
  std::string db;
  bool json = false;
};

/// The listing as one JSON document: every run with its status as shown (a run stored as
/// running that no process records is `interrupted`), times as ISO-8601 UTC text.
void print_runs_json(const std::string& path, const std::vector<tocd::db::RunSummary>& runs) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& s : runs) {
    list.push_back({{"run_id", s.run.id},
                    {"name", tocd::printable_text(s.run.name)},
                    {"status", tocd::db::to_string(tocd::db::shown_status(s))},
                    {"stored_status", tocd::db::to_string(s.run.status)},
                    {"recording_now", s.live},
                    {"started_utc", tocd::format_utc(s.run.started_utc_ns)},
                    {"ended_utc", s.run.ended_utc_ns ? nlohmann::json(tocd::format_utc(*s.run.ended_utc_ns))
                                                     : nlohmann::json(nullptr)},
                    {"steps", s.steps},
                    {"predictions", s.predictions},
                    {"events", s.events}});
  }
  tocd::cli::print_json({{"database", tocd::db::display_location(path)}, {"runs", list}});
}

void list_runs(const RunsOptions& o) {
  const std::string& path = o.db;
  const tocd::db::Reader reader(path);
  const auto runs = reader.runs();
  if (o.json) {
    print_runs_json(path, runs);
    return;
  }
  if (runs.empty()) {
    std::cout << "no runs in " << tocd::db::display_location(path) << '\n';
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
  auto o = std::make_shared<RunsOptions>();
  tocd::cli::add_runs_database(cmd, o->db);
  cmd->add_flag("--json", o->json, "print the runs as one JSON document");
  cmd->callback([o] { list_runs(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(runs, install_runs);

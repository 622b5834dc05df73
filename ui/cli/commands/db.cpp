// `tocdlab db push`: copies the runs of a rig's local file to a lab's PostgreSQL server
// (store-and-forward, docs/database.md "Pushing runs to a server").
#include <iostream>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "db_location_option.hpp"
#include "output_naming.hpp"
#include "tocd/db/location.hpp"
#include "tocd/db/push.hpp"

namespace {

struct PushOptions {
  std::string from, to;
  bool json = false;
};

void push(const PushOptions& o) {
  namespace db = tocd::db;
  db::PushOptions options;
  options.on_run = [](const db::PushedRun& r) {
    if (r.action == db::PushAction::skipped)
      std::cerr << fmt::format("run {} is recording right now; it is pushed by a push after it ends\n",
                               r.local_id);
  };
  const auto runs = db::push_runs(o.from, o.to, options);
  int count[4] = {};
  for (const auto& r : runs) ++count[static_cast<int>(r.action)];
  if (o.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& r : runs)
      list.push_back(
          {{"local_run_id", r.local_id},
           {"server_run_id", r.server_id == 0 ? nlohmann::json(nullptr) : nlohmann::json(r.server_id)},
           {"uuid", r.uuid},
           {"status", r.status},
           {"action", db::to_string(r.action)},
           {"samples", r.samples}});
    tocd::cli::print_json({{"from", o.from}, {"to", db::display_location(o.to)}, {"runs", list}});
  } else {
    std::cout << fmt::format("{:>5}  {:>6}  {:<11}  {:<9}  {:>9}  {}\n", "local", "server", "status",
                             "action", "samples", "uuid");
    for (const auto& r : runs)
      std::cout << fmt::format("{:>5}  {:>6}  {:<11}  {:<9}  {:>9}  {}\n", r.local_id,
                               r.server_id == 0 ? std::string("-") : std::to_string(r.server_id), r.status,
                               db::to_string(r.action), r.samples, r.uuid);
  }
  std::cerr << fmt::format(
      "pushed {} to {}: {} copied, {} updated, {} already there, {} recording (skipped)\n", o.from,
      db::display_location(o.to), count[0], count[1], count[2], count[3]);
}

void install_db(CLI::App& root) {
  auto* cmd = root.add_subcommand("db", "Measurement database tools (see docs/database.md)");
  cmd->require_subcommand(1);
  auto* p = cmd->add_subcommand(
      "push", "Copy the runs of a local database file to a PostgreSQL server, each run whole, idempotently");
  auto o = std::make_shared<PushOptions>();
  p->add_option("--from", o->from, "the local measurement database file")
      ->required()
      ->check(CLI::ExistingFile);
  p->add_option("--to", o->to, "the server: postgresql://[user@]host[:port]/database[?sslmode=...]")
      ->required();
  p->add_flag("--json", o->json, "print what was pushed as one JSON document");
  p->callback([o] { push(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(db, install_db);

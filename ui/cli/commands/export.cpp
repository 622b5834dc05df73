// `tocdlab export`: a run as CSV (steps, samples or events) or as one JSON document.
#include "tocd/db/export.hpp"

#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "command_registry.hpp"
#include "db_location_option.hpp"
#include "numeric_options.hpp"
#include "output_naming.hpp"
#include "output_paths.hpp"
#include "tocd/core/atomic_file.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/reader.hpp"

namespace cli = tocd::cli;

namespace {

struct ExportOptions {
  std::string db, format = "csv", table = "steps", out;
  std::int64_t run = 0;
  std::size_t max_points = 0;
};

void export_run(const ExportOptions& o) {
  const tocd::db::Reader reader(o.db);
  reader.run(o.run);  // unknown run: error before any output file is created
  // A file appears only when complete (a full disk leaves no truncated export behind).
  std::optional<tocd::AtomicFile> file;
  if (!o.out.empty()) file.emplace(o.out);
  std::ostream& out = file ? file->stream() : std::cout;
  if (o.format == "json") {
    tocd::db::JsonExportOptions jo;
    jo.max_points_per_channel = o.max_points;
    tocd::db::write_json(reader, o.run, jo, out);
  } else {
    const auto table = o.table == "samples"  ? tocd::db::CsvTable::samples
                       : o.table == "events" ? tocd::db::CsvTable::events
                                             : tocd::db::CsvTable::steps;
    tocd::db::write_csv(reader, o.run, table, out);
  }
  if (file) {
    file->commit();
    cli::announce_file(o.format == "json" ? "JSON export" : "CSV export", o.out);
  }
}

void install_export(CLI::App& root) {
  auto* cmd = root.add_subcommand("export", "Export a run as CSV or JSON");
  auto o = std::make_shared<ExportOptions>();
  cli::add_runs_database(cmd, o->db);
  cli::add_run_id(cmd, o->run);
  cmd->add_option("--format", o->format, "csv or json")
      ->check(CLI::IsMember({"csv", "json"}))
      ->capture_default_str();
  cmd->add_option("--table", o->table, "CSV table: steps, samples or events")
      ->check(CLI::IsMember({"steps", "samples", "events"}))
      ->capture_default_str();
  cmd->add_option("--max-points", o->max_points, "JSON: at most this many samples per channel (0 = all)")
      ->check(cli::whole_in(std::uint64_t{0}, std::uint64_t{100000000}))
      ->capture_default_str();
  cmd->add_option("-o,--output", o->out, "output file (default: standard output)")->check(cli::output_file());
  cmd->add_option("--out", o->out, "deprecated: use -o/--output")->check(cli::output_file())->group("");
  cmd->callback([o] { export_run(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(export, install_export);

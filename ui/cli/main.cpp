// tocdlab: the command line of the tissue-optical-clearing lab workbench.
#include <algorithm>
#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "command_registry.hpp"
#include "numeric_options.hpp"
#include "tocd/core/error.hpp"
#include "tocd/core/log.hpp"
#include "tocd/core/version.hpp"
#include "tocd/sim/parallel/team.hpp"

namespace {

// Under MPI an error on any rank ends the whole job: the others may be waiting for it in a
// collective. The message says which rank failed.
int fail(const char* kind, const char* what, int status) {
  auto& team = tocd::sim::parallel::world();
  if (team.size() > 1) {
    std::cerr << "tocdlab: " << kind << " (rank " << team.rank() << " of " << team.size() << "): " << what
              << std::endl;
    team.abort(status);
  }
  std::cerr << "tocdlab: " << kind << ": " << what << '\n';
  tocd::sim::parallel::finish_world();
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  // Started by mpirun/srun: join the job now. Only rank 0 prints data; the others' standard
  // output is discarded so that `--json` stays one document.
  auto& team = tocd::sim::parallel::world();
  if (team.rank() != 0) std::cout.rdbuf(nullptr);

  CLI::App app{
      "tocdlab — tissue optical clearing lab workbench: instruments, measurement "
      "database, FE + Monte Carlo prediction"};
  app.set_version_flag("-V,--version", std::string("tocdlab ") + std::string(tocd::version()));
  app.require_subcommand(0, 1);
  std::string log_level = "warn";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error, critical or off")
      ->capture_default_str();
  // Runs after parsing, before any subcommand's callback, so commands log at the chosen level.
  app.parse_complete_callback([&log_level] { tocd::set_log_level(log_level); });

  auto& registry = tocd::cli::command_registry();
  std::sort(registry.begin(), registry.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  for (const auto& entry : registry) entry.install(app);
  tocd::cli::check_numeric_syntax(app);
  // Bad options read like every other error, and exit 1 like them (CLI11's own codes are
  // 100-120, which scripts would have to know).
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return std::string("tocdlab: error: ") + e.what() + "\nRun with --help for more information.\n";
  });

  try {
    app.parse(argc, argv);  // subcommand callbacks run inside parse
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e) == 0 ? 0 : 1;  // --help and --version exit 0
    tocd::sim::parallel::finish_world();
    return status;
  } catch (const tocd::Error& e) {
    return fail("error", e.what(), 1);
  } catch (const std::exception& e) {
    return fail("internal error", e.what(), 2);
  }
  if (app.get_subcommands().empty()) std::cout << app.help();
  tocd::sim::parallel::finish_world();
  return 0;
}

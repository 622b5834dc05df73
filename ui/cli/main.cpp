// tocdlab: the command line of the tissue-optical-clearing lab workbench.
#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "command_registry.hpp"
#include "numeric_options.hpp"
#include "progress.hpp"
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

// CLI11 checks required options before unknown ones, so `tocdlab mc --bogus` would complain
// about the missing --optics and never mention the typo. An unknown argument is the likelier
// mistake: name it first.
std::string usage_message(const CLI::App& app, const CLI::ParseError& e) {
  if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr) {
    const std::vector<std::string> extras = app.remaining(true);
    if (!extras.empty()) {
      std::string list;
      for (const auto& x : extras) list += (list.empty() ? "" : " ") + x;
      return "unknown argument" + std::string(extras.size() > 1 ? "s: " : ": ") + list;
    }
  }
  return e.what();
}

/// Every byte of data must reach standard output: a full disk (or /dev/full) under `> FILE`
/// is an error, never an exit 0 with an empty file. Empty when all was written, else why not.
std::string stdout_problem() {
  // MPI ranks other than 0 discard their standard output (main): nothing to check there.
  if (std::cout.rdbuf() == nullptr) return {};
  std::cout.flush();
  errno = 0;
  const bool flushed = std::fflush(stdout) == 0;
  const int error = errno;
  if (flushed && !std::ferror(stdout) && std::cout.good()) return {};
  return fmt::format("writing standard output failed{} (disk full?); the output is incomplete",
                     error != 0 ? ": " + std::string(std::strerror(error)) : std::string());
}

/// The end of a command that succeeded: exit 0 only when its output was all written.
int finish_ok() {
  if (const std::string problem = stdout_problem(); !problem.empty())
    return fail("error", problem.c_str(), 1);
  tocd::sim::parallel::finish_world();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) must not kill the program between two writes with SIGXFSZ:
  // ignored, a write beyond the limit fails with EFBIG, and that takes the disk-full path
  // (the run ends interrupted and resumable, what was committed stays; an output file is an
  // error naming it).
  std::signal(SIGXFSZ, SIG_IGN);

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
  app.add_option("--log-level", log_level,
                 "trace, debug, info, warn, error, critical or off (debug: run phases; trace: every "
                 "instrument frame)")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "no progress display on stderr (errors are still reported)");
  // Runs after parsing, before any subcommand's callback, so commands log at the chosen level.
  app.parse_complete_callback([&log_level, &quiet] {
    tocd::set_log_level(log_level);
    tocd::cli::set_progress_quiet(quiet);
  });

  auto& registry = tocd::cli::command_registry();
  std::sort(registry.begin(), registry.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  for (const auto& entry : registry) entry.install(app);
  tocd::cli::check_numeric_syntax(app);

  // Exit status (docs/cli.md): 0 ok, 1 error, 2 usage. CLI11's own codes (100-120) would be
  // one more table for scripts to know; every command-line mistake is a usage error.
  try {
    app.parse(argc, argv);           // subcommand callbacks run inside parse
  } catch (const CLI::Success& e) {  // --help, --help-all, --version: on stdout
    app.exit(e);
    return finish_ok();
  } catch (const CLI::ParseError& e) {
    std::cerr << "tocdlab: usage error: " << usage_message(app, e)
              << "\nRun with --help for more information.\n";
    tocd::sim::parallel::finish_world();
    return 2;
  } catch (const tocd::Error& e) {
    return fail("error", e.what(), 1);
  } catch (const std::exception& e) {
    return fail("internal error", e.what(), 1);
  }
  if (app.get_subcommands().empty()) std::cout << app.help();
  return finish_ok();
}

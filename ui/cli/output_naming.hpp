#pragma once

// One naming table for what the command line writes (docs/cli.md, "Names"): a standard error is
// NAME_se next to NAME, steps are numbered from 1 in a field called `step`, units sit in the
// name. The simulator's and the run engine's own JSON keep their shapes; these functions bring
// them to the table at the one place where the command line prints them.

#include <string>

#include <nlohmann/json.hpp>

namespace tocd::cli {

/// Rewrites a JSON document to the naming table, recursively:
/// - an estimate object `"K": {"mean": m, "se": s}` becomes `"K": m, "K_se": s`;
/// - a key ending in `_stderr` ends in `_se` instead;
/// - an element of a `steps` array with a 0-based `index` gets `"step": index + 1` instead.
nlohmann::json to_naming_table(nlohmann::json j);

/// The same for a CSV table: `_stderr` -> `_se` in the header, CRLF -> LF throughout.
std::string to_naming_table_csv(const std::string& csv);

}  // namespace tocd::cli

namespace tocd::cli {

/// The one JSON document of a `--json` run, in the naming table, on stdout.
void print_json(const nlohmann::json& j);

/// "wrote PATH" on stderr (nothing with --quiet): files are announced, never mixed into data.
void announce_file(const std::string& what, const std::string& path);

/// Threads for "0 = all cores" options: the machine's hardware threads, at least 1.
int resolve_threads(int requested);

}  // namespace tocd::cli

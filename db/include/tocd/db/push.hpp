#pragma once

// Store-and-forward: copies the runs of a rig's local SQLite file to a lab's PostgreSQL
// server (`tocdlab db push`, docs/database.md "Pushing runs to a server").

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace tocd::db {

/// What a push did with one run of the file.
enum class PushAction {
  copied,     // the server did not have it: now it has the whole run
  updated,    // the server had an older state of it (interrupted, then resumed): replaced whole
  unchanged,  // the server has it as it is in the file: nothing written
  skipped,    // recording right now in a live process: pushed by a later push, once it has ended
};
std::string_view to_string(PushAction action) noexcept;

struct PushedRun {
  std::int64_t local_id = 0;
  std::int64_t server_id = 0;  // 0 when skipped
  std::string uuid;
  std::string status;  // as pushed (a run the file holds as running but nobody records: interrupted)
  PushAction action = PushAction::unchanged;
  std::int64_t samples = 0;  // samples of the run (written when copied or updated)
};

struct PushOptions {
  /// Called after each run, for progress messages (stderr in the CLI).
  std::function<void(const PushedRun&)> on_run;
};

/// Copies every run of the tocdlab file `from` to the server `to` (a postgresql:// URI),
/// creating the schema in an empty server database. Idempotent by run UUID: a run the
/// server already has as it is in the file is not written again. Each run is copied in one
/// server transaction, so the server shows a run whole or not at all; a push that stops
/// (server gone, killed) leaves the runs it committed, and the next push continues with the
/// rest. Two pushes of the same run at once are serialised on the server (an advisory lock
/// per run), so it arrives once. The file is only read.
///
/// Throws DatabaseError naming the run and what failed; runs pushed before are kept.
std::vector<PushedRun> push_runs(const std::filesystem::path& from, const std::string& to,
                                 const PushOptions& options = {});

}  // namespace tocd::db

#pragma once

// What ending and resuming a run mean, whichever backend stores it: a run found cut off gets
// its end and the event that says so; a resumed one, where its new segment's clock starts and
// the gap event. The backends read the run's last record and anchors and write what these
// decide.

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "tocd/db/database.hpp"
#include "tocd/db/records.hpp"

namespace tocd::db::detail {

/// The resume point of `run` at monotonic time `now_ns` and UTC `wall_ns`, its last record at
/// `last_t_ns` (none when nothing was recorded) and `anchors` its segments so far: the gap's
/// ends and the gap event to insert (its id left for the backend).
ResumePoint plan_resume(const RunRecord& run, const std::vector<RunAnchor>& anchors,
                        std::optional<std::int64_t> last_t_ns, int first_incomplete_step, std::int64_t now_ns,
                        std::int64_t wall_ns);

/// Throws DatabaseError when `run` cannot be resumed: it is completed, or still running
/// (`held_elsewhere()`, asked only then, tells whether another process records it).
void require_resumable(const RunRecord& run, const std::function<bool()>& held_elsewhere);

/// A resumed run's resume point: `p` with `run`, running again and no longer ended.
ResumePoint resumed(ResumePoint p, RunRecord run);

/// A run left `running` by a process that no longer records it, found on opening the store:
/// when it ended (the UTC of its last record, none when nothing was recorded) and the
/// `interrupted` event to insert.
struct CutOff {
  std::optional<std::int64_t> ended_utc_ns;
  EventRecord event;
};
CutOff cut_off(const RunRecord& run, const std::vector<RunAnchor>& anchors,
               std::optional<std::int64_t> last_t_ns);

}  // namespace tocd::db::detail

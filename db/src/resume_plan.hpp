#pragma once

// What resuming a run means, whichever backend stores it: where the new segment's clock starts
// and the gap event that says so. The backends read the run's last record and anchors, and
// write the anchor, the status and the event; this decides what they write.

#include <cstdint>
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

}  // namespace tocd::db::detail

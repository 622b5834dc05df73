// What ending and resuming a run mean, whichever backend stores it (resume_plan.hpp).
#include "resume_plan.hpp"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "tocd/core/clock.hpp"

namespace tocd::db::detail {

void require_resumable(const RunRecord& run, const std::function<bool()>& held_elsewhere) {
  if (run.status == RunStatus::completed)
    throw DatabaseError(fmt::format("run {} is completed; there is nothing to resume", run.id));
  if (run.status == RunStatus::running)
    throw DatabaseError(fmt::format("run {} is still running{}; it cannot be resumed", run.id,
                                    held_elsewhere() ? " in another process" : ""));
}

ResumePoint resumed(ResumePoint p, RunRecord run) {
  run.status = RunStatus::running;
  run.ended_utc_ns.reset();
  p.run = std::move(run);
  return p;
}

ResumePoint plan_resume(const RunRecord& run, const std::vector<RunAnchor>& anchors,
                        std::optional<std::int64_t> last_t_ns, int first_incomplete_step, std::int64_t now_ns,
                        std::int64_t wall_ns) {
  ResumePoint p;
  p.first_incomplete_step = first_incomplete_step;
  // The resumed segment's clock starts after everything recorded, so t_ns stays ordered also
  // when a sped-up simulated clock ran ahead of the monotonic one or the machine rebooted
  // (its monotonic clock restarted behind where the run's last segment began).
  p.gap_to_t_ns = last_t_ns ? std::max(now_ns, *last_t_ns + 1) : now_ns;
  p.gap_from_t_ns = last_t_ns.value_or(p.gap_to_t_ns);
  const std::int64_t segment_began = anchors.empty() ? run.monotonic_anchor_ns : anchors.back().monotonic_ns;
  const bool clock_restarted = segment_began > now_ns;
  p.gap_event.run_id = run.id;
  p.gap_event.t_ns = p.gap_to_t_ns;
  p.gap_event.kind = "gap";
  p.gap_event.step_index = first_incomplete_step;
  // Steps are numbered from 1 wherever a user reads them (step_index stays 0-based).
  const int step_shown = first_incomplete_step + 1;
  if (!last_t_ns) {
    p.gap_event.message = fmt::format("resumed (was {}, nothing recorded yet); continuing at step {}",
                                      to_string(run.status), step_shown);
  } else {
    // The gap in real time: UTC of the last record (by its segment's anchor) to now.
    const std::int64_t last_utc =
        anchors.empty() ? run.to_utc_ns(*last_t_ns) : utc_ns(anchors, anchors.back().segment, *last_t_ns);
    p.gap_event.message =
        fmt::format("resumed after a gap of {:.3f} s (was {}{}); continuing at step {}",
                    static_cast<double>(wall_ns - last_utc) * 1e-9, to_string(run.status),
                    clock_restarted ? "; the monotonic clock restarted, see run_anchors" : "", step_shown);
  }
  p.gap_event.data_json = fmt::format(R"({{"gap_from_t_ns":{},"gap_to_t_ns":{},"resumed_utc_ns":{}}})",
                                      p.gap_from_t_ns, p.gap_to_t_ns, wall_ns);
  return p;
}

CutOff cut_off(const RunRecord& run, const std::vector<RunAnchor>& anchors,
               std::optional<std::int64_t> last_t_ns) {
  const RunAnchor a = anchors.empty() ? RunAnchor{run.id, 0, run.wall_anchor_utc_ns, run.monotonic_anchor_ns,
                                                  run.clock_factor}
                                      : anchors.back();
  CutOff c;
  if (last_t_ns) c.ended_utc_ns = utc_ns({a}, a.segment, *last_t_ns);
  c.event.run_id = run.id;
  c.event.t_ns = last_t_ns.value_or(a.monotonic_ns);
  c.event.kind = "state";
  c.event.message = "interrupted: the recording process ended without closing the run (found on open " +
                    format_utc(wall_clock_ns()) + ")";
  return c;
}

}  // namespace tocd::db::detail

#pragma once

// Both backends' record queries under one name each: rows::find_run(c, id) is detail::find_run
// for an SQLite connection and pg::find_run for a server's, picked by the type of `c`. Code
// that serves a file and a server alike writes the call once, with `c` of either type.

#include <cstdint>

#include "pg/pg_rows.hpp"
#include "resume_plan.hpp"
#include "rows.hpp"
#include "tocd/core/clock.hpp"

namespace tocd::db::rows {

using detail::find_run;
using detail::first_incomplete_step;
using detail::instruments;
using detail::last_recorded_t_ns;
using detail::require_run;  // one template for both
using detail::run_anchors;
using detail::run_channels;
using detail::run_events;
using detail::run_predictions;
using detail::run_steps;
using detail::specimen;
using pg::find_run;
using pg::first_incomplete_step;
using pg::instruments;
using pg::last_recorded_t_ns;
using pg::run_anchors;
using pg::run_channels;
using pg::run_events;
using pg::run_predictions;
using pg::run_steps;
using pg::specimen;

/// Where run `r` resumes now (resume_plan.hpp), from what `c` stores of it, and the UTC that
/// pairs with the point's gap_to_t_ns in the new segment's anchor. Read inside the resume's
/// transaction.
struct ResumeNow {
  ResumePoint point;
  std::int64_t wall_ns = 0;
};
template <class Connection>
ResumeNow plan_resume_now(const Connection& c, const RunRecord& r) {
  const int first_incomplete = first_incomplete_step(c, r.id);
  const auto last = last_recorded_t_ns(c, r.id);
  const auto anchors = run_anchors(c, r.id);
  const std::int64_t now = monotonic_ns();
  const std::int64_t wall = wall_clock_ns();
  return {detail::plan_resume(r, anchors, last, first_incomplete, now, wall), wall};
}

}  // namespace tocd::db::rows

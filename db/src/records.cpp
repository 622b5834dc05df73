#include "tocd/db/records.hpp"

#include <cmath>
#include <string>

#include "tocd/db/database.hpp"

namespace tocd::db {

std::string_view to_string(RunStatus status) noexcept {
  switch (status) {
    case RunStatus::running:
      return "running";
    case RunStatus::completed:
      return "completed";
    case RunStatus::aborted:
      return "aborted";
    case RunStatus::interrupted:
      return "interrupted";
  }
  return "unknown";
}

RunStatus run_status_from_string(std::string_view text) {
  for (auto s : {RunStatus::running, RunStatus::completed, RunStatus::aborted, RunStatus::interrupted})
    if (to_string(s) == text) return s;
  throw DatabaseError("unknown run status '" + std::string(text) +
                      "' (expected running, completed, aborted or interrupted)");
}

std::int64_t utc_ns(const std::vector<RunAnchor>& anchors, int segment, std::int64_t t_ns) noexcept {
  const RunAnchor* use = nullptr;
  for (const auto& a : anchors)  // ordered by segment
    if (a.segment <= segment) use = &a;
  if (!use && !anchors.empty()) use = &anchors.front();
  if (!use) return t_ns;
  return use->wall_utc_ns + std::llround(static_cast<double>(t_ns - use->monotonic_ns) / use->clock_factor);
}

}  // namespace tocd::db

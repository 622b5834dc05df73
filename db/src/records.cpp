#include "tocd/db/records.hpp"

#include <cmath>
#include <string>

#include "tocd/core/enum_names.hpp"
#include "tocd/db/database.hpp"

namespace tocd::db {

namespace {
constexpr std::array<EnumName<RunStatus>, 4> kRunStatusNames{{{RunStatus::running, "running"},
                                                              {RunStatus::completed, "completed"},
                                                              {RunStatus::aborted, "aborted"},
                                                              {RunStatus::interrupted, "interrupted"}}};
}  // namespace

std::string_view to_string(RunStatus status) noexcept {
  return name_of(kRunStatusNames, status);
}

RunStatus run_status_from_string(std::string_view text) {
  if (const auto s = value_of(kRunStatusNames, text)) return *s;
  throw DatabaseError("unknown run status '" + std::string(text) + "' (expected " +
                      name_list(kRunStatusNames) + ")");
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

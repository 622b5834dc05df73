// Keys of a JSON config object that tocdlab reads: anything else is a typo or a field from
// another version, and is refused by name rather than ignored (a misspelled key must never
// give a default prediction as if it had been read).
#pragma once

#include <algorithm>
#include <initializer_list>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "tocd/core/error.hpp"

namespace tocd::sim::study {

/// Throws ConfigError "`where`: unknown key "K" (known: ...)" for the first key of `j` (an
/// object) that is not in `known`.
inline void require_known_keys(const nlohmann::json& j, std::initializer_list<std::string_view> known,
                               std::string_view where) {
  if (!j.is_object()) return;
  for (const auto& [key, value] : j.items()) {
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string list;
    for (const auto k : known) list += (list.empty() ? "" : ", ") + std::string(k);
    // dump() escapes control characters, so the key reaches the terminal as text.
    throw tocd::ConfigError(std::string(where) + ": unknown key " + nlohmann::json(key).dump() +
                            " (known: " + list + ")");
  }
}

}  // namespace tocd::sim::study

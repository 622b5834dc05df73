#pragma once
// Helpers of the MPI identity tests: what to leave out when two results are compared.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

namespace tocd::testing {

/// Removes the keys of a JSON document that report time, caching or the process layout
/// (seconds, rates, `cached`, `threads`, `ranks`) rather than the physics, at every depth.
inline void drop_run_facts(nlohmann::json& j) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end();) {
      const std::string& k = it.key();
      if (k.find("seconds") != std::string::npos || k.find("per_second") != std::string::npos ||
          k == "cached" || k == "threads" || k == "ranks")
        it = j.erase(it);
      else
        drop_run_facts(*it++);
    }
  } else if (j.is_array()) {
    for (auto& e : j) drop_run_facts(e);
  }
}

}  // namespace tocd::testing

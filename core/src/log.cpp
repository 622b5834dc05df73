#include "tocd/core/log.hpp"

#include <mutex>
#include <string>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "tocd/core/error.hpp"

namespace tocd {

namespace {
std::mutex registry_mutex;  // guards creation, so two threads never register one name twice
}

std::shared_ptr<spdlog::logger> logger(std::string_view module) {
  const std::string name(module);
  std::lock_guard lock(registry_mutex);
  if (auto existing = spdlog::get(name)) return existing;
  // Log lines go to stderr so that JSON and tables on stdout stay machine-readable.
  auto created = spdlog::stderr_color_mt(name);
  created->set_pattern("[%H:%M:%S.%e] [%n] [%^%l%$] %v");
  created->set_level(spdlog::get_level());
  return created;
}

void set_log_level(std::string_view level) {
  const auto parsed = spdlog::level::from_str(std::string(level));
  if (parsed == spdlog::level::off && level != "off") {
    throw ConfigError("unknown log level '" + std::string(level) +
                      "' (expected trace, debug, info, warn, error, critical or off)");
  }
  spdlog::set_level(parsed);
}

}  // namespace tocd

#pragma once

#include <memory>
#include <string_view>

#include <spdlog/logger.h>

namespace tocd {

/// The logger of one module ("mc", "fe", "devices", ...). All loggers share one sink and one
/// level, so the prefix tells where a line came from. Thread-safe.
std::shared_ptr<spdlog::logger> logger(std::string_view module);

/// Sets the level of every tocdlab logger ("trace" .. "off"); unknown names raise ConfigError.
void set_log_level(std::string_view level);

}  // namespace tocd

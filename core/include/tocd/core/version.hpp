#pragma once

#include <string_view>

namespace tocd {

/// The tocdlab release (semantic version), stored with every run and prediction.
std::string_view version() noexcept;

}  // namespace tocd

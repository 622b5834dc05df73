#pragma once

#include <string_view>

namespace tocd {

/// The tocdlab release (semantic version), stored with every run and prediction.
std::string_view version() noexcept;

/// `git describe --always --dirty` of the source tree when the build was configured, or
/// "unknown" when it was built outside a git checkout (e.g. from a release tarball). Stored
/// with every run.
std::string_view git_commit() noexcept;

}  // namespace tocd

#pragma once

namespace tocd {

/// Makes sure $XDG_RUNTIME_DIR names a private directory before a Qt application starts.
/// Without one (a root shell, a container, ssh without a login session) Qt warns on every
/// start and falls back to a directory of its own; this sets it to an existing private
/// directory, or creates /tmp/tocdlab-runtime-<uid> (mode 0700, owned by this user) and uses
/// that. A value that already names a usable directory is left alone; nothing is thrown.
void ensure_runtime_dir() noexcept;

}  // namespace tocd

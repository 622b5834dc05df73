#pragma once

#include <string>

namespace tocd::db::detail {

/// A random (version 4, RFC 4122) UUID in canonical lower-case text.
std::string random_uuid();

}  // namespace tocd::db::detail

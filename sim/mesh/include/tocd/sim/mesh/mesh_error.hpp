#pragma once

#include "tocd/core/error.hpp"

namespace tocd::sim::mesh {

/// A mesh that cannot be used as given: unreadable file, inverted, non-manifold or
/// non-conforming element. The message names the file and line, or the tet and its face.
using MeshError = tocd::ErrorOf<struct MeshModule, tocd::Error>;

}  // namespace tocd::sim::mesh

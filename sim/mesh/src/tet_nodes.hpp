#pragma once

// A tet's node indices against the mesh's nodes: one check and one message for the
// validation and for the adjacency, which may be built without it.

#include <cstddef>

#include "tocd/sim/mesh/tet_mesh.hpp"

namespace tocd::sim::mesh::detail {

/// Throws MeshError naming tet t and the index when one of its nodes is not in the mesh.
void check_tet_nodes(const TetMesh& mesh, std::size_t t);

}  // namespace tocd::sim::mesh::detail

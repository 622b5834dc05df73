#pragma once

#include <filesystem>

#include "tocd/sim/mesh/tet_mesh.hpp"

namespace tocd::sim::mesh {

/// Reads TetGen's PREFIX.node and PREFIX.ele (first element attribute = region id, 0 when
/// absent) and PREFIX.face when it exists (boundary markers). Indices may start at 0 or 1, as
/// TetGen allows; the result is 0-based. Throws MeshError naming the file and line.
TetMesh read_tetgen(const std::filesystem::path& prefix);

/// Writes PREFIX.node, PREFIX.ele (region as attribute) and PREFIX.face (boundary faces with
/// markers), 0-based, in a form read_tetgen and TetGen's tools read back.
void write_tetgen(const TetMesh& mesh, const std::filesystem::path& prefix);

}  // namespace tocd::sim::mesh

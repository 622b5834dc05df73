#pragma once

#include <atomic>
#include <string>

#include "plc.hpp"
#include "tocd/sim/mesh/tet_mesh.hpp"

namespace tocd::sim::geometry::detail {

/// Meshes the complex with TetGen (`switches` without the output-format letters this adds),
/// in a child process (TetGen can neither be interrupted nor trusted on its error path).
/// Tets carry TetGen's region attribute (the seed's region; a pocket no seed reached gets a
/// number above them: see assign_regions), boundary faces the marker of their surface. Throws
/// GeometryError naming the surfaces TetGen found at fault, and tocd::Cancelled (the child
/// killed) once `cancel` is set. A quadrant complex (`plc.quadrant`) comes back as the whole
/// box: its mesh mirrored across x = 0, then y = 0, the symmetry planes' faces dropped.
tocd::sim::mesh::TetMesh tetrahedralize(const Plc& plc, const Section& section, const std::string& switches,
                                        const std::atomic<bool>* cancel = nullptr);

}  // namespace tocd::sim::geometry::detail

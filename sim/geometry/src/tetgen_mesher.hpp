#pragma once

#include <string>

#include "plc.hpp"
#include "tocd/sim/mesh/tet_mesh.hpp"

namespace tocd::sim::geometry::detail {

/// Meshes the complex with TetGen (`switches` without the output-format letters this adds).
/// Tets carry their region, boundary faces the marker of their surface. Throws GeometryError
/// naming the surfaces TetGen found at fault.
tocd::sim::mesh::TetMesh tetrahedralize(const Plc& plc, const Section& section, const std::string& switches);

}  // namespace tocd::sim::geometry::detail

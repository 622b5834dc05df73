#pragma once

// Region of a point of the revolved complex, read off the r-z section. Every half-plane
// through the axis cuts the complex in a copy of the section scaled in r, so a point's
// section coordinates are exact and so is its region.

#include <array>

#include "layout.hpp"
#include "tocd/sim/mesh/tet_mesh.hpp"

namespace tocd::sim::geometry::detail {

/// Section coordinates (r, z) of the 3D point p of the complex revolved with n azimuths.
Vec2 section_point(const std::array<double, 3>& p, int azimuth_segments);

/// Region (pin, slide, air, skin, compressed) containing the section point q; q must not lie
/// on a surface.
int region_at(const Layout& layout, Vec2 q);

/// Gives every tet its region. TetGen numbers the regions it finds from the seeds; a closed
/// pocket no seed reached (a sliver of native skin cut off between a compressed outline and
/// the skin top, an air gap closed between skin and pin) gets a number of its own. Each
/// TetGen region is classified from its tets' centroids: pockets take the region they lie
/// in, and a seeded region whose tets disagree with its seed is an error (a surface that is
/// not closed, or a seed outside its region).
void assign_regions(tocd::sim::mesh::TetMesh& mesh, const Layout& layout, int azimuth_segments);

}  // namespace tocd::sim::geometry::detail

#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "tocd/sim/mc/huge_page_allocator.hpp"
#include "tocd/sim/mesh/tet_mesh.hpp"
#include "tocd/sim/mesh/topology.hpp"

namespace tocd::sim::mc {

/// Where a boundary face sits on the mesh's bounding box (z is up).
enum class Side : std::int8_t { bottom, top, sides };

/// The per-tet geometry the transport kernel reads at every step: the four outward face
/// planes (n . x = offset on the face) in single precision, one 64-byte cache line per tet.
/// Face f is the face opposite the tet's local node f. Single precision puts a plane within
/// ~1e-6 mm of the double one; the kernel clamps the resulting tiny negative distances.
struct alignas(64) KernelTet {
  float nx[4], ny[4], nz[4], offset[4];
};

/// The per-tet topology, read when a packet reaches a face: the next tet across each face
/// (>= 0) or the boundary group of the face (-1 - group), the optics slot of the tet's
/// region and of each neighbour's (-1 on the boundary), so a crossing needs no load from
/// the next tet to decide whether the refractive index changes. 32 bytes.
struct alignas(32) KernelLink {
  std::int32_t next[4];
  std::int16_t next_slot[4];
  std::int16_t region_slot;
  std::int16_t pad_[3];
};

/// A class of boundary faces that photons exit through, tallied together.
struct BoundaryGroup {
  std::int32_t marker = 0;
  Side side = Side::sides;
};

/// A mesh validated and laid out for transport. Build once, run many times.
struct PreparedMesh {
  mesh::TetMesh mesh;  ///< the input, kept for sources and output
  /// Kernel records in kernel order: tets sorted along a Morton (Z-order) curve of their
  /// centroids, so neighbours sit close in memory. Results are reported in input order.
  std::vector<KernelTet, HugePageAllocator<KernelTet>> tets;
  std::vector<KernelLink, HugePageAllocator<KernelLink>> links;  ///< same order as tets
  std::vector<std::int32_t> original_of;                         ///< kernel index -> input tet index
  std::vector<double> volume_mm3;                                ///< per input tet
  std::vector<std::int32_t> region_ids;                          ///< region id of each optics slot, ascending
  std::vector<BoundaryGroup> groups;  ///< boundary groups referenced by KernelTet::next
  mesh::BoundingBox box;
  /// Kernel planes and positions are relative to this point (the box centre), which keeps
  /// single-precision plane offsets accurate for meshes far from the coordinate origin.
  std::array<double, 3> origin{0.0, 0.0, 0.0};
};

/// Validates the mesh (throws mesh::MeshError naming the tet and face) and builds the
/// kernel layout. Boundary faces are classified bottom / top / sides against the bounding
/// box: bottom = outward normal within 0.1 degree of -z and lying on the box's lowest z.
PreparedMesh prepare(mesh::TetMesh mesh);

/// The prepared mesh with other regions (one id per tet, input order): what prepare() gives
/// for the same tets with those regions, without validating and laying out the geometry again
/// (O(tets); the graded optics re-split the same mesh's skin for every strain of full
/// clearing). Throws mesh::MeshError when the count is not the mesh's or there are more than
/// 32767 distinct regions.
PreparedMesh relabel(const PreparedMesh& prepared, std::vector<std::int32_t> regions);

}  // namespace tocd::sim::mc

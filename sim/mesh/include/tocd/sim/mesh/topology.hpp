#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tocd/sim/mesh/tet_mesh.hpp"

namespace tocd::sim::mesh {

/// Local face f of a tet is the triangle opposite its local node f.
inline constexpr std::array<std::array<int, 3>, 4> kFaceLocalNodes = {
    {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}}};

/// Neighbours across each local face (-1 on the mesh boundary) and the boundary marker of
/// each boundary face (from TetMesh::boundary_faces, 0 when none is given).
struct FaceAdjacency {
  std::vector<std::array<std::int32_t, 4>> neighbour;
  std::vector<std::array<std::int32_t, 4>> boundary_marker;
};

/// Builds face adjacency. Throws MeshError when a face is shared by more than two tets
/// (non-manifold) or when a listed boundary face is not a face of any tet.
FaceAdjacency build_face_adjacency(const TetMesh& mesh);

/// A face plane: unit normal pointing out of the tet, and offset so that normal . x = offset
/// on the face; normal . x < offset inside the tet.
struct FacePlane {
  Point3 normal;
  double offset;
};

/// The four outward face planes of tet t (face f opposite local node f).
std::array<FacePlane, 4> face_planes(const TetMesh& mesh, std::size_t t);

/// Checks that the mesh can be transported through: node indices in range, one region per
/// tet, no inverted or degenerate tet, no face shared by more than two tets, and no
/// non-conforming contact (a tet face lying against another tet without sharing its nodes,
/// e.g. a hanging node). Throws MeshError naming the tet and face. Returns the adjacency
/// so callers need not build it twice. The same as check_elements, then check_topology.
FaceAdjacency validate(const TetMesh& mesh);

/// The checks of validate() that need no adjacency: node indices in range and coordinates
/// finite, one region per tet, no inverted or degenerate tet. Throws MeshError.
void check_elements(const TetMesh& mesh);

/// The rest of validate(), on a mesh that check_elements() passed: builds the adjacency,
/// checks that no face is shared by more than two tets and that no contact is non-conforming,
/// and returns the adjacency. Reads the mesh only, so it may run beside other readers.
FaceAdjacency check_topology(const TetMesh& mesh);

/// Axis-aligned bounding box of the nodes.
struct BoundingBox {
  Point3 min;
  Point3 max;
};
BoundingBox bounding_box(const TetMesh& mesh);

}  // namespace tocd::sim::mesh

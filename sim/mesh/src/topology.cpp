#include "tocd/sim/mesh/topology.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "tet_nodes.hpp"
#include "tocd/sim/mesh/mesh_error.hpp"

namespace tocd::sim::mesh {
namespace {

// A tet face keyed by its sorted global node triple, with the tet*4+face it belongs to.
// 16 bytes: the keys of a 200,000-tet mesh are 12 MB, and in a fresh allocation each page
// costs a fault.
struct FaceKey {
  std::array<std::int32_t, 3> nodes;
  std::int32_t owner;  // tet * 4 + local face
  bool operator<(const FaceKey& o) const { return nodes < o.nodes || (nodes == o.nodes && owner < o.owner); }
};

std::array<std::int32_t, 3> sorted(std::array<std::int32_t, 3> n) {
  std::sort(n.begin(), n.end());
  return n;
}

Point3 sub(const Point3& a, const Point3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Point3 cross(const Point3& a, const Point3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Point3& a, const Point3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Every tet face's key, in ascending order. A counting sort on the smallest node and then a
// sort of each node's few faces give the order that one sort of all 4 n keys gives (the
// keys are distinct: no two share an owner), without a second copy of the keys.
std::vector<FaceKey> sorted_face_keys(const TetMesh& mesh) {
  const std::size_t nt = mesh.tets.size();
  if (nt > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 4))
    throw MeshError(fmt::format("mesh has {} tets; at most {} are supported", nt,
                                std::numeric_limits<std::int32_t>::max() / 4));
  std::vector<std::size_t> start(mesh.nodes.size() + 1, 0);
  for (std::size_t t = 0; t < nt; ++t) {
    detail::check_tet_nodes(mesh, t);  // the counts below are indexed by node
    const auto& tet = mesh.tets[t];
    // A face's smallest node is the tet's smallest unless the face leaves that node out.
    for (int f = 0; f < 4; ++f) {
      const auto& l = kFaceLocalNodes[f];
      ++start[static_cast<std::size_t>(std::min({tet[l[0]], tet[l[1]], tet[l[2]]})) + 1];
    }
  }
  for (std::size_t n = 0; n + 1 < start.size(); ++n) start[n + 1] += start[n];
  std::vector<FaceKey> keys(nt * 4);
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tet = mesh.tets[t];
    for (int f = 0; f < 4; ++f) {
      const auto& l = kFaceLocalNodes[f];
      const FaceKey key{sorted({tet[l[0]], tet[l[1]], tet[l[2]]}), static_cast<std::int32_t>(t * 4) + f};
      keys[next[static_cast<std::size_t>(key.nodes[0])]++] = key;
    }
  }
  for (std::size_t n = 0; n + 1 < start.size(); ++n)
    std::sort(keys.begin() + static_cast<std::ptrdiff_t>(start[n]),
              keys.begin() + static_cast<std::ptrdiff_t>(start[n + 1]));
  return keys;
}

}  // namespace

FaceAdjacency build_face_adjacency(const TetMesh& mesh) {
  const std::size_t nt = mesh.tets.size();
  const std::vector<FaceKey> keys = sorted_face_keys(mesh);

  FaceAdjacency adj;
  adj.neighbour.assign(nt, {-1, -1, -1, -1});
  adj.boundary_marker.assign(nt, {0, 0, 0, 0});
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j].nodes == keys[i].nodes) ++j;
    if (j - i > 2) {
      throw MeshError(fmt::format(
          "non-manifold mesh: face ({} {} {}) of tet {} (local face {}) is shared by {} tets "
          "(tets {}, {}, {}...)",
          keys[i].nodes[0], keys[i].nodes[1], keys[i].nodes[2], keys[i].owner / 4, keys[i].owner % 4, j - i,
          keys[i].owner / 4, keys[i + 1].owner / 4, keys[i + 2].owner / 4));
    }
    if (j - i == 2) {
      const auto a = keys[i].owner, b = keys[i + 1].owner;
      adj.neighbour[a / 4][a % 4] = static_cast<std::int32_t>(b / 4);
      adj.neighbour[b / 4][b % 4] = static_cast<std::int32_t>(a / 4);
    }
    i = j;
  }

  // Markers of listed boundary faces. Listed faces between two tets (TetGen writes interior
  // facets too) carry no exit meaning and are skipped; a face matching no tet is an error.
  for (std::size_t k = 0; k < mesh.boundary_faces.size(); ++k) {
    const auto& bf = mesh.boundary_faces[k];
    const FaceKey probe{sorted(bf.nodes), -1};
    auto it = std::lower_bound(keys.begin(), keys.end(),
                               FaceKey{probe.nodes, std::numeric_limits<std::int32_t>::min()});
    if (it == keys.end() || it->nodes != probe.nodes) {
      throw MeshError(fmt::format("boundary face {} (nodes {} {} {}) is not a face of any tet", k,
                                  bf.nodes[0], bf.nodes[1], bf.nodes[2]));
    }
    const auto o = it->owner;
    if (adj.neighbour[o / 4][o % 4] < 0) adj.boundary_marker[o / 4][o % 4] = bf.marker;
  }
  return adj;
}

std::array<FacePlane, 4> face_planes(const TetMesh& mesh, std::size_t t) {
  std::array<FacePlane, 4> planes{};
  const auto& tet = mesh.tets[t];
  for (int f = 0; f < 4; ++f) {
    const auto& l = kFaceLocalNodes[f];
    const Point3& a = mesh.nodes[tet[l[0]]];
    Point3 n = cross(sub(mesh.nodes[tet[l[1]]], a), sub(mesh.nodes[tet[l[2]]], a));
    const double len = std::sqrt(dot(n, n));
    for (auto& c : n) c /= len;
    // Orient away from the opposite node.
    if (dot(n, sub(mesh.nodes[tet[f]], a)) > 0.0) {
      for (auto& c : n) c = -c;
    }
    planes[f] = {n, dot(n, a)};
  }
  return planes;
}

BoundingBox bounding_box(const TetMesh& mesh) {
  BoundingBox box{{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
  for (const auto& p : mesh.nodes) {
    for (int k = 0; k < 3; ++k) {
      box.min[k] = std::min(box.min[k], p[k]);
      box.max[k] = std::max(box.max[k], p[k]);
    }
  }
  return box;
}

namespace detail {

void check_tet_nodes(const TetMesh& mesh, std::size_t t) {
  const auto nn = static_cast<std::int64_t>(mesh.nodes.size());
  for (const std::int32_t node : mesh.tets[t])
    if (node < 0 || node >= nn)
      throw MeshError(fmt::format("tet {} refers to node {} but the mesh has {} nodes", t, node, nn));
}

}  // namespace detail

}  // namespace tocd::sim::mesh

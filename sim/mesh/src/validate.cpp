// Mesh validation: the checks a transport code needs before it trusts face adjacency.
#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "tet_nodes.hpp"
#include "tocd/sim/mesh/cell_buckets.hpp"
#include "tocd/sim/mesh/mesh_error.hpp"
#include "tocd/sim/mesh/topology.hpp"

namespace tocd::sim::mesh {
namespace {

double distance(const Point3& a, const Point3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

// Uniform grid of tet bounding boxes, for point location.
class TetGrid {
 public:
  explicit TetGrid(const TetMesh& mesh) : mesh_(mesh), box_(bounding_box(mesh)) {
    const double cells = std::max(1.0, std::cbrt(static_cast<double>(mesh.tets.size()) / 2.0));
    for (int k = 0; k < 3; ++k) {
      n_[k] = static_cast<int>(std::clamp(cells, 1.0, 256.0));
      h_[k] = std::max(box_.max[k] - box_.min[k], 1e-300) / n_[k];
    }
    auto buckets = bucket_by_cell(mesh.tets.size(), static_cast<std::size_t>(n_[0]) * n_[1] * n_[2],
                                  [&](std::size_t t, const auto& add) {
                                    std::array<int, 3> lo{}, hi{};
                                    tet_cells(t, lo, hi);
                                    for (int i = lo[0]; i <= hi[0]; ++i)
                                      for (int j = lo[1]; j <= hi[1]; ++j)
                                        for (int k = lo[2]; k <= hi[2]; ++k) add(index(i, j, k));
                                  });
    start_ = std::move(buckets.start);
    items_ = std::move(buckets.items);
  }

  // Tet (other than `skip`) that holds p strictly inside (by margin), or -1.
  std::int64_t find_strictly_containing(const Point3& p, double margin, std::size_t skip) const {
    std::array<int, 3> c{};
    for (int k = 0; k < 3; ++k) {
      const double u = (p[k] - box_.min[k]) / h_[k];
      if (u < 0.0 || u > n_[k]) return -1;
      c[k] = std::min(static_cast<int>(u), n_[k] - 1);
    }
    const std::size_t cell = index(c[0], c[1], c[2]);
    for (std::size_t i = start_[cell]; i < start_[cell + 1]; ++i) {
      const auto t = static_cast<std::size_t>(items_[i]);
      if (t == skip) continue;
      const auto planes = face_planes(mesh_, t);
      bool inside = true;
      for (const auto& pl : planes) {
        const double s = pl.normal[0] * p[0] + pl.normal[1] * p[1] + pl.normal[2] * p[2] - pl.offset;
        if (s > -margin) inside = false;
      }
      if (inside) return static_cast<std::int64_t>(t);
    }
    return -1;
  }

 private:
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * n_[1] + j) * n_[0] + i;
  }
  void tet_cells(std::size_t t, std::array<int, 3>& lo, std::array<int, 3>& hi) const {
    for (int k = 0; k < 3; ++k) {
      double a = HUGE_VAL, b = -HUGE_VAL;
      for (int v = 0; v < 4; ++v) {
        a = std::min(a, mesh_.nodes[mesh_.tets[t][v]][k]);
        b = std::max(b, mesh_.nodes[mesh_.tets[t][v]][k]);
      }
      lo[k] = std::clamp(static_cast<int>((a - box_.min[k]) / h_[k]), 0, n_[k] - 1);
      hi[k] = std::clamp(static_cast<int>((b - box_.min[k]) / h_[k]), 0, n_[k] - 1);
    }
  }

  const TetMesh& mesh_;
  BoundingBox box_;
  std::array<int, 3> n_{};
  std::array<double, 3> h_{};
  std::vector<std::size_t> start_;
  std::vector<std::int32_t> items_;
};

// A face with no neighbour must look out of the mesh. If a point just outside it lies inside
// another tet, the two tets touch without sharing the face: a hanging node or T-junction.
void check_conforming(const TetMesh& mesh, const FaceAdjacency& adj) {
  const TetGrid grid(mesh);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto planes = face_planes(mesh, t);
    for (int f = 0; f < 4; ++f) {
      if (adj.neighbour[t][f] >= 0) continue;
      const auto& l = kFaceLocalNodes[f];
      Point3 centroid{0, 0, 0};
      double size = 0.0;
      for (int v = 0; v < 3; ++v) {
        const Point3& p = mesh.nodes[mesh.tets[t][l[v]]];
        for (int k = 0; k < 3; ++k) centroid[k] += p[k] / 3.0;
        size = std::max(size, distance(p, mesh.nodes[mesh.tets[t][l[(v + 1) % 3]]]));
      }
      const double eps = 1e-4 * size;
      Point3 probe;
      for (int k = 0; k < 3; ++k) probe[k] = centroid[k] + eps * planes[f].normal[k];
      const auto other = grid.find_strictly_containing(probe, 1e-7 * size, t);
      if (other >= 0) {
        throw MeshError(
            fmt::format("non-conforming mesh: face {} of tet {} (nodes {} {} {}) lies against tet {} "
                        "without sharing its nodes (hanging node or overlapping tets)",
                        f, t, mesh.tets[t][l[0]], mesh.tets[t][l[1]], mesh.tets[t][l[2]], other));
      }
    }
  }
}

}  // namespace

void check_elements(const TetMesh& mesh) {
  if (mesh.tets.empty()) throw MeshError("mesh has no tetrahedra");
  if (mesh.regions.size() != mesh.tets.size()) {
    throw MeshError(fmt::format("mesh has {} tets but {} region ids", mesh.tets.size(), mesh.regions.size()));
  }
  // NaN or huge coordinates would pass the volume test (NaN compares false) and break the
  // point-location grid, so every node is checked first.
  for (std::size_t n = 0; n < mesh.nodes.size(); ++n) {
    for (int k = 0; k < 3; ++k) {
      if (!(std::abs(mesh.nodes[n][k]) <= kMaxCoordinateMm)) {
        throw MeshError(fmt::format("node {} has coordinate {} = {}; accepted -{:g} to {:g} mm", n, "xyz"[k],
                                    mesh.nodes[n][k], kMaxCoordinateMm, kMaxCoordinateMm));
      }
    }
  }
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    detail::check_tet_nodes(mesh, t);
    const auto& tet = mesh.tets[t];
    double longest = 0.0;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        longest = std::max(longest, distance(mesh.nodes[tet[a]], mesh.nodes[tet[b]]));
    const double v = tet_volume(mesh, t);
    // A regular tet of edge L has volume 0.118 L^3; 1e-9 L^3 is a sliver no ray test survives.
    if (v <= 1e-9 * longest * longest * longest) {
      throw MeshError(fmt::format("tet {} (nodes {} {} {} {}) is {} (signed volume {:.3g} mm^3)", t, tet[0],
                                  tet[1], tet[2], tet[3], v < 0.0 ? "inverted" : "degenerate", v));
    }
  }
}

FaceAdjacency check_topology(const TetMesh& mesh) {
  FaceAdjacency adj = build_face_adjacency(mesh);
  check_conforming(mesh, adj);
  return adj;
}

FaceAdjacency validate(const TetMesh& mesh) {
  check_elements(mesh);
  return check_topology(mesh);
}

}  // namespace tocd::sim::mesh

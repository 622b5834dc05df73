#include "tocd/sim/mc/prepared_mesh.hpp"

#include <algorithm>
#include <cmath>

namespace tocd::sim::mc {
namespace {

Side classify(const mesh::TetMesh& m, const std::array<std::int32_t, 4>& tet, int face, const mesh::FacePlane& plane,
              const mesh::BoundingBox& box) {
  const double diag = std::hypot(box.max[0] - box.min[0], box.max[1] - box.min[1], box.max[2] - box.min[2]);
  const double tol = 1e-9 * diag;
  const auto& l = mesh::kFaceLocalNodes[face];
  // cos(0.1 degree) = 0.9999985: a face tilted by more is not "down".
  constexpr double kCosTilt = 0.9999985;
  bool on_min = true, on_max = true;
  for (int v = 0; v < 3; ++v) {
    const double z = m.nodes[tet[l[v]]][2];
    on_min = on_min && z <= box.min[2] + tol;
    on_max = on_max && z >= box.max[2] - tol;
  }
  if (plane.normal[2] < -kCosTilt && on_min) return Side::bottom;
  if (plane.normal[2] > kCosTilt && on_max) return Side::top;
  return Side::sides;
}

}  // namespace

PreparedMesh prepare(mesh::TetMesh input) {
  PreparedMesh p;
  p.mesh = std::move(input);
  const auto& m = p.mesh;
  const mesh::FaceAdjacency adj = mesh::validate(m);
  p.box = mesh::bounding_box(m);

  p.region_ids = m.regions;
  std::sort(p.region_ids.begin(), p.region_ids.end());
  p.region_ids.erase(std::unique(p.region_ids.begin(), p.region_ids.end()), p.region_ids.end());

  const std::size_t nt = m.tets.size();
  p.tets.resize(nt);
  p.volume_mm3.resize(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    KernelTet& k = p.tets[t];
    const auto planes = mesh::face_planes(m, t);
    for (int f = 0; f < 4; ++f) {
      k.nx[f] = planes[f].normal[0];
      k.ny[f] = planes[f].normal[1];
      k.nz[f] = planes[f].normal[2];
      k.offset[f] = planes[f].offset;
      if (adj.neighbour[t][f] >= 0) {
        k.next[f] = adj.neighbour[t][f];
        continue;
      }
      const BoundaryGroup g{adj.boundary_marker[t][f], classify(m, m.tets[t], f, planes[f], p.box)};
      auto it = std::find_if(p.groups.begin(), p.groups.end(),
                             [&](const BoundaryGroup& x) { return x.marker == g.marker && x.side == g.side; });
      if (it == p.groups.end()) it = p.groups.insert(p.groups.end(), g);
      k.next[f] = -1 - static_cast<std::int32_t>(it - p.groups.begin());
    }
    k.region_slot = static_cast<std::int32_t>(
        std::lower_bound(p.region_ids.begin(), p.region_ids.end(), m.regions[t]) - p.region_ids.begin());
    k.pad_[0] = k.pad_[1] = k.pad_[2] = 0;
    p.volume_mm3[t] = mesh::tet_volume(m, t);
  }
  return p;
}

}  // namespace tocd::sim::mc

#include "tocd/sim/mc/prepared_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <system_error>

#include <fmt/format.h>

#include "tocd/sim/mesh/mesh_error.hpp"

namespace tocd::sim::mc {
namespace {

Side classify(const mesh::TetMesh& m, const std::array<std::int32_t, 4>& tet, int face,
              const mesh::FacePlane& plane, const mesh::BoundingBox& box) {
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

// Interleaves the low 21 bits of x, y, z.
std::uint64_t morton(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  auto spread = [](std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  return spread(x) | spread(y) << 1 | spread(z) << 2;
}

// Kernel order: by Morton code of the centroid, ties by input index (deterministic).
std::vector<std::int32_t> locality_order(const mesh::TetMesh& m, const mesh::BoundingBox& box) {
  const std::size_t nt = m.tets.size();
  std::vector<std::pair<std::uint64_t, std::int32_t>> keyed(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    std::uint32_t q[3];
    for (int k = 0; k < 3; ++k) {
      double c = 0.0;
      for (int v = 0; v < 4; ++v) c += 0.25 * m.nodes[m.tets[t][v]][k];
      const double span = box.max[k] - box.min[k];
      const double unit = span > 0.0 ? (c - box.min[k]) / span : 0.0;
      q[k] = static_cast<std::uint32_t>(std::clamp(unit, 0.0, 1.0) * 2097151.0);
    }
    keyed[t] = {morton(q[0], q[1], q[2]), static_cast<std::int32_t>(t)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::int32_t> order(nt);
  for (std::size_t i = 0; i < nt; ++i) order[i] = keyed[i].second;
  return order;
}

// The ascending distinct region ids: the optics slots.
std::vector<std::int32_t> distinct_regions(std::vector<std::int32_t> regions) {
  std::sort(regions.begin(), regions.end());
  regions.erase(std::unique(regions.begin(), regions.end()), regions.end());
  if (regions.size() > 32767) {
    throw mesh::MeshError(
        fmt::format("mesh has {} distinct regions; at most 32767 are supported", regions.size()));
  }
  return regions;
}

std::int16_t slot_in(const std::vector<std::int32_t>& region_ids, std::int32_t region) {
  return static_cast<std::int16_t>(std::lower_bound(region_ids.begin(), region_ids.end(), region) -
                                   region_ids.begin());
}

// Each kernel tet's face planes, relative to the kernel origin (in double before rounding).
void fill_planes(PreparedMesh& p) {
  const auto& m = p.mesh;
  for (std::size_t kt = 0; kt < p.tets.size(); ++kt) {
    const auto planes = mesh::face_planes(m, static_cast<std::size_t>(p.original_of[kt]));
    KernelTet& k = p.tets[kt];
    for (int f = 0; f < 4; ++f) {
      k.nx[f] = static_cast<float>(planes[f].normal[0]);
      k.ny[f] = static_cast<float>(planes[f].normal[1]);
      k.nz[f] = static_cast<float>(planes[f].normal[2]);
      const double shift = planes[f].normal[0] * p.origin[0] + planes[f].normal[1] * p.origin[1] +
                           planes[f].normal[2] * p.origin[2];
      k.offset[f] = static_cast<float>(planes[f].offset - shift);
    }
  }
}

// Each kernel tet's neighbours and their optics slots; a boundary face leads to its group.
void fill_links(PreparedMesh& p, const mesh::FaceAdjacency& adj) {
  const auto& m = p.mesh;
  const auto slot_of = [&](std::int32_t region) { return slot_in(p.region_ids, region); };
  const std::size_t nt = m.tets.size();
  std::vector<std::int32_t> kernel_of(nt);
  for (std::size_t i = 0; i < nt; ++i)
    kernel_of[static_cast<std::size_t>(p.original_of[i])] = static_cast<std::int32_t>(i);
  for (std::size_t kt = 0; kt < nt; ++kt) {
    const auto t = static_cast<std::size_t>(p.original_of[kt]);
    KernelLink& link = p.links[kt];
    for (int f = 0; f < 4; ++f) {
      if (adj.neighbour[t][f] >= 0) {
        link.next[f] = kernel_of[static_cast<std::size_t>(adj.neighbour[t][f])];
        link.next_slot[f] = slot_of(m.regions[static_cast<std::size_t>(adj.neighbour[t][f])]);
        continue;
      }
      link.next_slot[f] = -1;
      const auto plane = mesh::face_planes(m, t)[static_cast<std::size_t>(f)];
      const BoundaryGroup g{adj.boundary_marker[t][f], classify(m, m.tets[t], f, plane, p.box)};
      auto it = std::find_if(p.groups.begin(), p.groups.end(), [&](const BoundaryGroup& x) {
        return x.marker == g.marker && x.side == g.side;
      });
      if (it == p.groups.end()) it = p.groups.insert(p.groups.end(), g);
      link.next[f] = -1 - static_cast<std::int32_t>(it - p.groups.begin());
    }
    link.region_slot = slot_of(m.regions[t]);
    link.pad_[0] = link.pad_[1] = link.pad_[2] = 0;
  }
}

}  // namespace

PreparedMesh prepare(mesh::TetMesh input) {
  PreparedMesh p;
  p.mesh = std::move(input);
  const auto& m = p.mesh;
  mesh::check_elements(m);
  // The adjacency and the conformity check that needs it take as long as the kernel's
  // geometry and need none of it: they run beside it, on a second thread. The mesh is only
  // read until both are done. Where no thread can be started, it runs in turn.
  const auto check = [&m] { return mesh::check_topology(m); };
  std::future<mesh::FaceAdjacency> topology;
  try {
    topology = std::async(std::launch::async, check);
  } catch (const std::system_error&) {
    topology = std::async(std::launch::deferred, check);
  }
  p.box = mesh::bounding_box(m);
  for (int k = 0; k < 3; ++k) p.origin[k] = 0.5 * (p.box.min[k] + p.box.max[k]);
  const std::size_t nt = m.tets.size();
  p.original_of = locality_order(m, p.box);
  p.tets.resize(nt);
  p.links.resize(nt);
  p.volume_mm3.resize(nt);
  for (std::size_t t = 0; t < nt; ++t) p.volume_mm3[t] = mesh::tet_volume(m, t);
  fill_planes(p);
  const mesh::FaceAdjacency adj = topology.get();  // a bad mesh's MeshError, first
  p.region_ids = distinct_regions(m.regions);
  fill_links(p, adj);
  return p;
}

PreparedMesh relabel(const PreparedMesh& prepared, std::vector<std::int32_t> regions) {
  if (regions.size() != prepared.mesh.tets.size())
    throw mesh::MeshError(
        fmt::format("relabel: {} regions for a mesh of {} tets", regions.size(), prepared.mesh.tets.size()));
  PreparedMesh p = prepared;
  p.region_ids = distinct_regions(regions);
  p.mesh.regions = std::move(regions);
  const auto& region = p.mesh.regions;
  for (std::size_t kt = 0; kt < p.links.size(); ++kt) {
    KernelLink& link = p.links[kt];
    link.region_slot = slot_in(p.region_ids, region[static_cast<std::size_t>(p.original_of[kt])]);
    for (int f = 0; f < 4; ++f) {
      if (link.next[f] < 0) continue;  // a boundary face: its slot stays -1
      const auto neighbour = static_cast<std::size_t>(p.original_of[static_cast<std::size_t>(link.next[f])]);
      link.next_slot[f] = slot_in(p.region_ids, region[neighbour]);
    }
  }
  return p;
}

}  // namespace tocd::sim::mc

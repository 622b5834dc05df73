#include "tocd/sim/mesh/tet_mesh.hpp"

namespace tocd::sim::mesh {

double signed_volume(const Point3& a, const Point3& b, const Point3& c, const Point3& d) noexcept {
  const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  const double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
  return (ux * (vy * wz - vz * wy) - uy * (vx * wz - vz * wx) + uz * (vx * wy - vy * wx)) / 6.0;
}

double tet_volume(const TetMesh& mesh, std::size_t t) noexcept {
  const auto& tet = mesh.tets[t];
  return signed_volume(mesh.nodes[tet[0]], mesh.nodes[tet[1]], mesh.nodes[tet[2]], mesh.nodes[tet[3]]);
}

double region_volume(const TetMesh& mesh, std::int32_t region) {
  double total = 0.0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    if (region < 0 || mesh.regions[t] == region) total += tet_volume(mesh, t);
  }
  return total;
}

}  // namespace tocd::sim::mesh

#include "region_classifier.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <vector>

#include <fmt/format.h>

namespace tocd::sim::geometry::detail {

namespace {

/// Even-odd rule; the polygon is closed implicitly.
bool inside(const std::vector<Vec2>& poly, Vec2 q) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 a = poly[i], b = poly[j];
    if ((a.z > q.z) != (b.z > q.z) && q.r < a.r + (q.z - a.z) / (b.z - a.z) * (b.r - a.r)) in = !in;
  }
  return in;
}

const char* region_name(int region) {
  switch (region) {
    case pin:
      return "glass pin";
    case slide:
      return "glass slide";
    case air:
      return "air";
    case skin:
      return "skin";
    case compressed:
      return "compressed skin";
    default:
      return "no region";
  }
}

}  // namespace

Vec2 section_point(const std::array<double, 3>& p, int n) {
  // Between two azimuths the revolved complex is the section swept linearly from one
  // half-plane to the next: a point at section radius r has r cos(pi / n) as its component
  // along the sector's bisector, whatever its place in the sector.
  const double step = 2.0 * std::numbers::pi / n;
  double phi = std::atan2(p[1], p[0]);
  if (phi < 0) phi += 2.0 * std::numbers::pi;
  const double mid = (std::floor(phi / step) + 0.5) * step;
  const double along = p[0] * std::cos(mid) + p[1] * std::sin(mid);
  return {along / std::cos(0.5 * step), p[2]};
}

int region_at(const Layout& L, Vec2 q) {
  if (q.z < 0) return slide;
  if (q.r >= L.r_core_mm) return q.z < L.skin_top_mm ? skin : air;
  if (inside(L.pin_polygon, q)) return pin;
  for (const auto& poly : L.compressed_polygons)
    if (inside(poly, q)) return compressed;
  if (!L.skin_polygon.empty() && inside(L.skin_polygon, q)) return skin;
  return air;
}

namespace {

std::array<double, 3> centroid(const tocd::sim::mesh::TetMesh& mesh, std::size_t t) {
  std::array<double, 3> c{0, 0, 0};
  for (const auto node : mesh.tets[t])
    for (int k = 0; k < 3; ++k) c[k] += 0.25 * mesh.nodes[static_cast<std::size_t>(node)][k];
  return c;
}

// A tet whose centroid the section polygons put outside its TetGen region, with that region
// within one tet size of the centroid in the section: a sliver on a curved or slanted
// interface. There the revolved complex TetGen meshed (flat facets between half-planes) and
// the section polygons the classifier reads part by a fraction of a tet. (A surface that is
// not closed leaves whole regions of tets on the wrong side, far from it.)
bool near_region(const tocd::sim::mesh::TetMesh& mesh, std::size_t t, const Layout& L, int n, int region) {
  const auto& tet = mesh.tets[t];
  double size = 0;
  for (std::size_t a = 0; a < 4; ++a)
    for (std::size_t b = a + 1; b < 4; ++b) {
      const auto& p = mesh.nodes[static_cast<std::size_t>(tet[a])];
      const auto& q = mesh.nodes[static_cast<std::size_t>(tet[b])];
      size = std::max(size, std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
    }
  const Vec2 c = section_point(centroid(mesh, t), n);
  constexpr int directions = 16;
  for (const double radius : {0.25 * size, 0.5 * size, size})
    for (int k = 0; k < directions; ++k) {
      const double a = 2.0 * std::numbers::pi * k / directions;
      if (region_at(L, {c.r + radius * std::cos(a), c.z + radius * std::sin(a)}) == region) return true;
    }
  return false;
}

}  // namespace

void assign_regions(tocd::sim::mesh::TetMesh& mesh, const Layout& L, int n) {
  struct Group {
    std::array<std::size_t, 6> tets{};
    std::size_t example[6]{};
  };
  std::map<std::int32_t, Group> groups;
  std::vector<int> by_centroid(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const int r = region_at(L, section_point(centroid(mesh, t), n));
    by_centroid[t] = r;
    Group& g = groups[mesh.regions[t]];
    if (g.tets[r]++ == 0) g.example[r] = t;
  }
  // Slivers on an interface count with their group's region; what is left over is real.
  for (auto& [attribute, g] : groups) {
    const auto r = static_cast<int>(std::max_element(g.tets.begin(), g.tets.end()) - g.tets.begin());
    const std::size_t majority = g.tets[static_cast<std::size_t>(r)];
    std::size_t minority = 0;
    for (const std::size_t count : g.tets) minority += count;
    minority -= majority;
    if (minority == 0 || minority * 1000 > majority) continue;  // many: an open surface, said below
    g.tets.fill(0);
    g.tets[static_cast<std::size_t>(r)] = majority;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      if (mesh.regions[t] != attribute || by_centroid[t] == r) continue;
      if (near_region(mesh, t, L, n, r)) {
        ++g.tets[static_cast<std::size_t>(r)];
      } else if (g.tets[static_cast<std::size_t>(by_centroid[t])]++ == 0) {
        g.example[by_centroid[t]] = t;
      }
    }
  }
  for (auto& [attribute, g] : groups) {
    const auto most = std::max_element(g.tets.begin(), g.tets.end());
    const auto r = static_cast<std::size_t>(most - g.tets.begin());
    for (std::size_t other = 0; other < g.tets.size(); ++other) {
      if (other == r || g.tets[other] == 0) continue;
      const auto& c = mesh.nodes[static_cast<std::size_t>(mesh.tets[g.example[other]][0])];
      throw GeometryError(
          fmt::format("composite mesh: one TetGen region holds {} {} tets and {} {} tets (one near x = "
                      "{:.4f}, y = {:.4f}, z = {:.4f} mm): a surface of the composite is not closed",
                      g.tets[r], region_name(static_cast<int>(r)), g.tets[other],
                      region_name(static_cast<int>(other)), c[0], c[1], c[2]));
    }
    g.example[0] = r;  // the group's region
  }
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    mesh.regions[t] = static_cast<std::int32_t>(groups.at(mesh.regions[t]).example[0]);
}

}  // namespace tocd::sim::geometry::detail

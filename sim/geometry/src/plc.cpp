#include "plc.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>

#include <fmt/format.h>

namespace tocd::sim::geometry::detail {

namespace {

constexpr double kRingJitter = 1e-9;  ///< full width of a ring point's relative radial perturbation

/// A number in [0, 1) fixed by (a, b): splitmix64's finaliser of the pair.
double unit_hash(int a, int b) {
  std::uint64_t x =
      (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return static_cast<double>(x >> 11) * 0x1.0p-53;
}

class PlcBuilder {
 public:
  PlcBuilder(const Layout& layout, int n) : L_(layout), n_(n) {}

  Plc build() {
    const double H = L_.half_mm;
    std::vector<double> heights{-L_.slide_thickness_mm, 0.0};
    if (!L_.baseline) heights.push_back(L_.skin_top_mm);
    heights.push_back(L_.z_top_mm);
    for (double z : heights) corners_[z] = add_square(H, z);

    // Box: bottom, sides (one rectangle per layer and side: slide, skin, air), air top
    // around the pin.
    add_facet({{corners_.at(heights.front())}}, {}, kSlideBottom);
    for (std::size_t k = 0; k + 1 < heights.size(); ++k) {
      const auto& lo = corners_.at(heights[k]);
      const auto& hi = corners_.at(heights[k + 1]);
      const int surface = k == 0 ? kSlideSides : (k + 2 == heights.size() ? kAirSides : kSkinSides);
      for (int c = 0; c < 4; ++c)
        add_facet({{{lo[c], lo[(c + 1) % 4], hi[(c + 1) % 4], hi[c]}}}, {}, surface);
    }
    const auto pin_ring = ring(L_.pin_top_vertex);
    add_facet({{corners_.at(L_.z_top_mm)}, {pin_ring}}, {{0.0, 0.0, L_.z_top_mm}}, kAirTop);
    add_facet({{pin_ring}}, {}, kPinTop);

    for (std::size_t p = 0; p < L_.planes.size(); ++p) add_plane(static_cast<int>(p));
    const auto& s = L_.section;
    for (const auto& e : s.edges) {
      if (plane_of_edge(L_, e) >= 0) continue;
      const auto a = ring(e.a), b = ring(e.b);
      if (a.size() == 1 && b.size() == 1) continue;  // along the axis
      for (int k = 0; k < n_; ++k) {
        const int k1 = (k + 1) % n_;
        std::vector<int> poly;
        if (a.size() == 1) {
          poly = {a[0], b[k], b[k1]};
        } else if (b.size() == 1) {
          poly = {a[k], a[k1], b[0]};
        } else {
          // Two triangles: the ring points are perturbed (ring, below), so the trapezoid is
          // planar only to 1e-9 of its radius.
          add_facet({{{a[k], a[k1], b[k1]}}}, {}, e.surface);
          poly = {a[k], b[k1], b[k]};
        }
        add_facet({{poly}}, {}, e.surface);
      }
    }
    add_seeds();
    return std::move(plc_);
  }

 private:
  int add_point(double x, double y, double z) {
    plc_.points.push_back({x, y, z});
    return static_cast<int>(plc_.points.size()) - 1;
  }

  std::vector<int> add_square(double H, double z) {
    return {add_point(-H, -H, z), add_point(H, -H, z), add_point(H, H, z), add_point(-H, H, z)};
  }

  /// The N ring points of a section vertex (one point on the axis), created once. Each point's
  /// radius is perturbed within +-kRingJitter / 2 of itself, by a fixed hash of the vertex and
  /// the azimuth (the same mesh on every run and machine). Unperturbed, every ring is cocircular
  /// and the tip's rings lie on one sphere, so TetGen's insphere tests on them are degenerate to
  /// the last bit: its floating-point filter fails and exact arithmetic decides (a quarter of the
  /// meshing time). The perturbation, at most 3e-9 mm on the 5.6 mm core, is far below every
  /// optical scale and far above the filter's threshold (about 1e-15 of the local edge).
  const std::vector<int>& ring(int vertex) {
    auto it = rings_.find(vertex);
    if (it != rings_.end()) return it->second;
    const Vec2 v = L_.section.vertices[static_cast<std::size_t>(vertex)];
    std::vector<int> ids;
    if (v.r == 0) {
      ids.push_back(add_point(0, 0, v.z));
    } else {
      for (int k = 0; k < n_; ++k) {
        const double phi = 2.0 * std::numbers::pi * k / n_;
        const double r = v.r * (1 + kRingJitter * (unit_hash(vertex, k) - 0.5));
        ids.push_back(add_point(r * std::cos(phi), r * std::sin(phi), v.z));
      }
    }
    return rings_.emplace(vertex, std::move(ids)).first->second;
  }

  void add_facet(std::vector<std::vector<int>> polygons, std::vector<std::array<double, 3>> holes,
                 int surface) {
    Facet f;
    for (auto& p : polygons) f.polygons.push_back({std::move(p)});
    f.holes = std::move(holes);
    f.surface = surface;
    plc_.facets.push_back(std::move(f));
  }

  /// A plane of the box: the square with a ring for every section vertex on it that another
  /// surface ends at, and a hole in every annulus no section edge covers.
  void add_plane(int p) {
    const auto& s = L_.section;
    const double z = L_.planes[static_cast<std::size_t>(p)].z;
    std::vector<std::pair<double, double>> covered{{L_.r_core_mm, std::numeric_limits<double>::infinity()}};
    std::vector<bool> ends_other(s.vertices.size(), false), on_plane(s.vertices.size(), false);
    for (const auto& e : s.edges) {
      if (plane_of_edge(L_, e) == p) {
        const double ra = s.vertices[static_cast<std::size_t>(e.a)].r,
                     rb = s.vertices[static_cast<std::size_t>(e.b)].r;
        covered.push_back({std::min(ra, rb), std::max(ra, rb)});
        on_plane[static_cast<std::size_t>(e.a)] = on_plane[static_cast<std::size_t>(e.b)] = true;
      } else {
        ends_other[static_cast<std::size_t>(e.a)] = ends_other[static_cast<std::size_t>(e.b)] = true;
      }
    }
    const auto is_covered = [&](double r) {
      return std::any_of(covered.begin(), covered.end(),
                         [&](auto iv) { return iv.first <= r && r <= iv.second; });
    };
    std::vector<int> ring_vertices;
    for (std::size_t i = 0; i < s.vertices.size(); ++i) {
      if (s.vertices[i].z != z || !(on_plane[i] || ends_other[i])) continue;
      const double r = s.vertices[i].r;
      const double eps = 1e-7;
      // A ring is needed where another surface ends on the plane or where coverage changes.
      const bool transition = is_covered(r - eps) != is_covered(r + eps);
      if (ends_other[i] || (transition && r > 0)) ring_vertices.push_back(static_cast<int>(i));
    }
    std::sort(ring_vertices.begin(), ring_vertices.end(), [&](int a, int b) {
      return s.vertices[static_cast<std::size_t>(a)].r < s.vertices[static_cast<std::size_t>(b)].r;
    });
    std::vector<std::vector<int>> polygons{corners_.at(z)};
    std::vector<std::array<double, 3>> holes;
    double previous = 0;
    for (int v : ring_vertices) {
      const double r = s.vertices[static_cast<std::size_t>(v)].r;
      if (r > previous && !is_covered(0.5 * (previous + r))) holes.push_back({0.5 * (previous + r), 0.0, z});
      polygons.push_back(ring(v));
      previous = r;
    }
    if (previous < L_.r_core_mm && !is_covered(0.5 * (previous + L_.r_core_mm)))
      holes.push_back({0.5 * (previous + L_.r_core_mm), 0.0, z});
    add_facet(std::move(polygons), std::move(holes), L_.planes[static_cast<std::size_t>(p)].surface);
  }

  void add_seeds() {
    const double c = 0.95 * L_.half_mm;
    plc_.seeds.push_back({{c, c, -0.5 * L_.slide_thickness_mm}, slide});
    if (!L_.baseline) plc_.seeds.push_back({{c, c, 0.5 * L_.skin_top_mm}, skin});
    plc_.seeds.push_back({{c, c, 0.5 * (L_.skin_top_mm + L_.z_top_mm)}, air});
    const Vec2 p = interior_point(L_.pin_polygon);
    plc_.seeds.push_back({{p.r, 0.0, p.z}, pin});
    for (const auto& poly : L_.compressed_polygons) {
      const Vec2 q = interior_point(poly);
      plc_.seeds.push_back({{q.r, 0.0, q.z}, compressed});
    }
  }

  const Layout& L_;
  int n_;
  Plc plc_;
  std::map<int, std::vector<int>> rings_;
  std::map<double, std::vector<int>> corners_;
};

}  // namespace

Plc build_plc(const Layout& layout, int azimuth_segments) {
  return PlcBuilder(layout, azimuth_segments).build();
}

}  // namespace tocd::sim::geometry::detail

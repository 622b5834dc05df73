#include "plc.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <set>

#include <fmt/format.h>

#include "tocd/sim/geometry/composite.hpp"

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
  PlcBuilder(const Layout& layout, int n) : L_(layout), n_(n), q_(n / 4) {}

  Plc build() {
    if (n_ < 8 || n_ % 4 != 0)
      throw GeometryError(fmt::format(
          "composite mesh: {} azimuth segments; the quadrant complex needs a multiple of 4 (at least 8)",
          n_));
    const double H = L_.half_mm;
    std::vector<double> heights{-L_.slide_thickness_mm, 0.0};
    if (!L_.baseline) heights.push_back(L_.skin_top_mm);
    heights.push_back(L_.z_top_mm);
    for (double z : heights) corners_[z] = {add_point(H, 0, z), add_point(H, H, z), add_point(0, H, z)};

    // Box: bottom, the two outer sides (one rectangle per layer and side: slide, skin, air),
    // air top around the pin.
    add_quarter_annulus(heights.front(), nullptr, nullptr, kSlideBottom);
    for (std::size_t k = 0; k + 1 < heights.size(); ++k) {
      const auto& lo = corners_.at(heights[k]);
      const auto& hi = corners_.at(heights[k + 1]);
      const int surface = k == 0 ? kSlideSides : (k + 2 == heights.size() ? kAirSides : kSkinSides);
      for (int c = 0; c < 2; ++c) add_facet({{lo[c], lo[c + 1], hi[c + 1], hi[c]}}, surface);
    }
    const std::vector<int>& pin_ring = ring(L_.pin_top_vertex);
    add_quarter_annulus(L_.z_top_mm, &pin_ring, nullptr, kAirTop);
    add_quarter_annulus(L_.z_top_mm, nullptr, &pin_ring, kPinTop);

    for (std::size_t p = 0; p < L_.planes.size(); ++p) add_plane(static_cast<int>(p));
    const auto& s = L_.section;
    for (const auto& e : s.edges) {
      if (plane_of_edge(L_, e) >= 0) continue;
      const auto& a = ring(e.a);
      const auto& b = ring(e.b);
      if (a.size() == 1 && b.size() == 1) continue;  // along the axis
      for (int k = 0; k < q_; ++k) {
        const int k1 = k + 1;
        if (a.size() == 1) {
          add_facet({a[0], b[k], b[k1]}, e.surface);
        } else if (b.size() == 1) {
          add_facet({a[k], a[k1], b[0]}, e.surface);
        } else {
          // Two triangles: the ring points are perturbed (ring, below), so the trapezoid is
          // planar only to 1e-9 of its radius.
          add_facet({a[k], a[k1], b[k1]}, e.surface);
          add_facet({a[k], b[k1], b[k]}, e.surface);
        }
      }
    }
    // Last: each symmetry plane holds every edge the facets above have in it.
    add_symmetry_plane(1, kSymmetryPlaneY);
    add_symmetry_plane(0, kSymmetryPlaneX);
    add_seeds();
    plc_.quadrant = true;
    return std::move(plc_);
  }

 private:
  int add_point(double x, double y, double z) {
    plc_.points.push_back({x, y, z});
    return static_cast<int>(plc_.points.size()) - 1;
  }

  /// The point of the axis at height z, created once (section vertices on the axis included).
  int axis_point(double z) {
    auto it = axis_.find(z);
    if (it != axis_.end()) return it->second;
    return axis_.emplace(z, add_point(0, 0, z)).first->second;
  }

  /// The ring points of a section vertex from azimuth 0 to 90 degrees (N / 4 + 1 of them; one
  /// point on the axis), created once. The first lies exactly in y = 0 and the last exactly in
  /// x = 0, so both are their own mirror images. Each point's radius is perturbed within
  /// +-kRingJitter / 2 of itself, by a fixed hash of the vertex and the azimuth (the same mesh
  /// on every run and machine). Unperturbed, every ring is cocircular and the tip's rings lie on
  /// one sphere, so TetGen's insphere tests on them are degenerate to the last bit: its
  /// floating-point filter fails and exact arithmetic decides (a quarter of the meshing time).
  /// The perturbation, at most 3e-9 mm on the 5.6 mm core, is far below every optical scale
  /// and far above the filter's threshold (about 1e-15 of the local edge).
  const std::vector<int>& ring(int vertex) {
    auto it = rings_.find(vertex);
    if (it != rings_.end()) return it->second;
    const Vec2 v = L_.section.vertices[static_cast<std::size_t>(vertex)];
    std::vector<int> ids;
    if (v.r == 0) {
      ids.push_back(axis_point(v.z));
    } else {
      for (int k = 0; k <= q_; ++k) {
        const double phi = 2.0 * std::numbers::pi * k / n_;
        const double r = v.r * (1 + kRingJitter * (unit_hash(vertex, k) - 0.5));
        const double x = k == q_ ? 0.0 : r * std::cos(phi);
        const double y = k == 0 ? 0.0 : r * std::sin(phi);
        ids.push_back(add_point(x, y, v.z));
      }
    }
    return rings_.emplace(vertex, std::move(ids)).first->second;
  }

  void add_facet(std::vector<int> polygon, int surface) {
    Facet f;
    f.polygons.push_back({std::move(polygon)});
    f.surface = surface;
    plc_.facets.push_back(std::move(f));
  }

  /// The part of the plane z between the ring `inner` (nullptr: the axis) and the ring `outer`
  /// (nullptr: the box's outer sides) in the quadrant: one polygon, out along y = 0, round the
  /// outer bound, in along x = 0 and back round the inner ring.
  void add_quarter_annulus(double z, const std::vector<int>* inner, const std::vector<int>* outer,
                           int surface) {
    std::vector<int> polygon{inner ? inner->front() : axis_point(z)};
    if (outer)
      polygon.insert(polygon.end(), outer->begin(), outer->end());
    else
      polygon.insert(polygon.end(), corners_.at(z).begin(), corners_.at(z).end());
    if (inner) polygon.insert(polygon.end(), inner->rbegin(), inner->rend() - 1);
    add_facet(std::move(polygon), surface);
  }

  /// A plane of the box: the quadrant cut by a ring at every section vertex on it that another
  /// surface ends at or where the coverage by section edges changes; the parts that a section
  /// edge (or, beyond the revolved core, the plane itself) covers are its facets.
  void add_plane(int p) {
    const auto& s = L_.section;
    const double z = L_.planes[static_cast<std::size_t>(p)].z;
    const int surface = L_.planes[static_cast<std::size_t>(p)].surface;
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
      // A ring is needed where another surface ends on the plane or where coverage changes;
      // a vertex on the axis is a corner of the quadrant's first part anyway.
      const bool transition = is_covered(r - eps) != is_covered(r + eps);
      if (r > 0 && (ends_other[i] || transition)) ring_vertices.push_back(static_cast<int>(i));
    }
    std::sort(ring_vertices.begin(), ring_vertices.end(), [&](int a, int b) {
      return s.vertices[static_cast<std::size_t>(a)].r < s.vertices[static_cast<std::size_t>(b)].r;
    });
    const std::vector<int>* inner = nullptr;  // the axis
    double previous = 0;
    for (int v : ring_vertices) {
      const double r = s.vertices[static_cast<std::size_t>(v)].r;
      const std::vector<int>& outer = ring(v);
      if (r > previous && is_covered(0.5 * (previous + r))) add_quarter_annulus(z, inner, &outer, surface);
      inner = &outer;
      previous = r;
    }
    if (previous >= L_.r_core_mm || is_covered(0.5 * (previous + L_.r_core_mm)))
      add_quarter_annulus(z, inner, nullptr, surface);
  }

  /// The symmetry plane where coordinate `axis` (0: x, 1: y) is 0: the rectangle from the
  /// axis to the box side and from the slide bottom to the top, with every edge of the other
  /// facets that lies in it as a segment (the r-z section, the planes' lines, the layers).
  void add_symmetry_plane(int axis, int surface) {
    const auto in_plane = [&](int point) {
      return plc_.points[static_cast<std::size_t>(point)][axis] == 0.0;
    };
    // The outline: up the axis, out along the top past the pin ring, down the box side.
    const int corner = axis == 1 ? 0 : 2;
    std::vector<int> outline;
    for (const auto& [z, id] : axis_) outline.push_back(id);
    const std::vector<int>& pin_ring = ring(L_.pin_top_vertex);
    outline.push_back(axis == 1 ? pin_ring.front() : pin_ring.back());
    for (auto it = corners_.rbegin(); it != corners_.rend(); ++it)
      outline.push_back(it->second[static_cast<std::size_t>(corner)]);
    std::set<std::pair<int, int>> on_outline;
    for (std::size_t i = 0; i < outline.size(); ++i) {
      const int a = outline[i], b = outline[(i + 1) % outline.size()];
      on_outline.insert({std::min(a, b), std::max(a, b)});
    }
    std::set<std::pair<int, int>> segments;
    for (const auto& f : plc_.facets)
      for (const auto& polygon : f.polygons) {
        const auto& v = polygon.vertices;
        for (std::size_t i = 0; i < v.size(); ++i) {
          const int a = v[i], b = v[(i + 1) % v.size()];
          if (a == b || !in_plane(a) || !in_plane(b)) continue;
          const std::pair<int, int> edge{std::min(a, b), std::max(a, b)};
          if (!on_outline.count(edge)) segments.insert(edge);
        }
      }
    Facet f;
    f.surface = surface;
    f.polygons.push_back({std::move(outline)});
    for (const auto& [a, b] : segments) f.polygons.push_back({{a, b}});
    plc_.facets.push_back(std::move(f));
  }

  /// Seeds at the azimuth of the first ring points off the symmetry planes, where the
  /// revolved surfaces pass through their section's vertices.
  void add_seeds() {
    const double c = 0.95 * L_.half_mm;
    plc_.seeds.push_back({{c, c, -0.5 * L_.slide_thickness_mm}, slide});
    if (!L_.baseline) plc_.seeds.push_back({{c, c, 0.5 * L_.skin_top_mm}, skin});
    plc_.seeds.push_back({{c, c, 0.5 * (L_.skin_top_mm + L_.z_top_mm)}, air});
    const double phi = 2.0 * std::numbers::pi / n_;
    const auto seed = [&](Vec2 p, int region) {
      plc_.seeds.push_back({{p.r * std::cos(phi), p.r * std::sin(phi), p.z}, region});
    };
    seed(interior_point(L_.pin_polygon), pin);
    for (const auto& poly : L_.compressed_polygons) seed(interior_point(poly), compressed);
  }

  const Layout& L_;
  int n_;
  int q_;  ///< azimuth segments in the quadrant
  Plc plc_;
  std::map<int, std::vector<int>> rings_;
  std::map<double, int> axis_;  ///< axis points by height
  std::map<double, std::vector<int>>
      corners_;  ///< the quadrant's outer corners (H,0), (H,H), (0,H) by height
};

}  // namespace

Plc build_plc(const Layout& layout, int azimuth_segments) {
  return PlcBuilder(layout, azimuth_segments).build();
}

}  // namespace tocd::sim::geometry::detail

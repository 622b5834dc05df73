#include "section.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "tocd/sim/geometry/composite.hpp"
#include "tocd/sim/geometry/douglas_peucker.hpp"

namespace tocd::sim::geometry::detail {

double norm(Vec2 a) {
  return std::hypot(a.r, a.z);
}

double segment_distance(Vec2 p, Vec2 a, Vec2 b, double* t_out) {
  const Vec2 ab = b - a;
  const double len2 = dot(ab, ab);
  double t = len2 > 0 ? dot(p - a, ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  if (t_out) *t_out = t;
  return norm(p - (a + t * ab));
}

void Section::add_edge(int a, int b, int surface) {
  if (a == b || has_edge(a, b)) return;
  edges.push_back({a, b, surface});
}

bool Section::has_edge(int a, int b) const {
  return std::any_of(edges.begin(), edges.end(),
                     [&](const Edge& e) { return (e.a == a && e.b == b) || (e.a == b && e.b == a); });
}

namespace {

int orientation(Vec2 a, Vec2 b, Vec2 c) {
  const double v = cross(b - a, c - a);
  const double scale = std::max({norm(b - a), norm(c - a), 1e-300});
  if (std::abs(v) <= 1e-14 * scale * scale) return 0;
  return v > 0 ? 1 : -1;
}

bool on_segment(Vec2 a, Vec2 b, Vec2 p) {
  return std::min(a.r, b.r) <= p.r && p.r <= std::max(a.r, b.r) && std::min(a.z, b.z) <= p.z &&
         p.z <= std::max(a.z, b.z);
}

std::string where(Vec2 p) {
  return fmt::format("(r = {:.4f} mm, z = {:.4f} mm)", p.r, p.z);
}

}  // namespace

bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
  const int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o1 != o2 && o3 != o4) return true;
  if (o1 == 0 && on_segment(a, b, c)) return true;
  if (o2 == 0 && on_segment(a, b, d)) return true;
  if (o3 == 0 && on_segment(c, d, a)) return true;
  if (o4 == 0 && on_segment(c, d, b)) return true;
  return false;
}

void check_section(const Section& s, double tol) {
  const auto& v = s.vertices;
  const auto name = [&](int surface) { return s.surfaces[static_cast<std::size_t>(surface)].name; };
  // Vertices closer than the tolerance to an edge they do not end: a touching or nearly
  // touching surface that TetGen would reject as a self-intersection.
  for (std::size_t i = 0; i < v.size(); ++i) {
    bool used = false;
    int surface_of_vertex = -1;
    for (const auto& e : s.edges) {
      if (e.a == static_cast<int>(i) || e.b == static_cast<int>(i)) {
        used = true;
        surface_of_vertex = e.surface;
        break;
      }
    }
    if (!used) continue;
    for (const auto& e : s.edges) {
      if (e.a == static_cast<int>(i) || e.b == static_cast<int>(i)) continue;
      if (segment_distance(v[i], v[static_cast<std::size_t>(e.a)], v[static_cast<std::size_t>(e.b)]) < tol) {
        throw GeometryError(fmt::format("{} touches {} at {}: surfaces must meet only at shared points",
                                        name(surface_of_vertex), name(e.surface), where(v[i])));
      }
    }
  }
  for (std::size_t i = 0; i < s.edges.size(); ++i) {
    const auto& e = s.edges[i];
    for (std::size_t j = i + 1; j < s.edges.size(); ++j) {
      const auto& f = s.edges[j];
      const bool share = e.a == f.a || e.a == f.b || e.b == f.a || e.b == f.b;
      const Vec2 a = v[static_cast<std::size_t>(e.a)], b = v[static_cast<std::size_t>(e.b)];
      const Vec2 c = v[static_cast<std::size_t>(f.a)], d = v[static_cast<std::size_t>(f.b)];
      if (share) {
        // Edges sharing a vertex may only meet there: reject collinear overlap.
        const int shared = (e.a == f.a || e.a == f.b) ? e.a : e.b;
        const Vec2 p = v[static_cast<std::size_t>(shared)];
        const Vec2 u = (shared == e.a ? b : a) - p, w = (shared == f.a ? d : c) - p;
        if (std::abs(cross(u, w)) <= 1e-12 * norm(u) * norm(w) && dot(u, w) > 0) {
          throw GeometryError(
              fmt::format("{} overlaps {} near {}", name(e.surface), name(f.surface), where(p)));
        }
        continue;
      }
      if (segments_intersect(a, b, c, d)) {
        throw GeometryError(
            fmt::format("{} intersects {} near {}", name(e.surface), name(f.surface), where(0.5 * (a + b))));
      }
    }
  }
}

double signed_area2(const std::vector<Vec2>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) a += cross(p[i], p[(i + 1) % p.size()]);
  return a;
}

double integral_r_dA(const std::vector<Vec2>& p) {
  // Green: int r dA = closed integral of (r^2 / 2) dz, exact on straight edges.
  double s = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2 a = p[i], b = p[(i + 1) % p.size()];
    s += (b.z - a.z) * (a.r * a.r + a.r * b.r + b.r * b.r) / 6.0;
  }
  return s;
}

Vec2 interior_point(const std::vector<Vec2>& p) {
  // Scan at several heights; take the widest inside interval (even-odd rule).
  double zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
  for (const auto& q : p) {
    zmin = std::min(zmin, q.z);
    zmax = std::max(zmax, q.z);
  }
  Vec2 best{};
  double best_width = -1;
  for (int k = 1; k < 16; ++k) {
    const double z = zmin + (zmax - zmin) * (k + 0.123456) / 16.0;
    std::vector<double> xs;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec2 a = p[i], b = p[(i + 1) % p.size()];
      if ((a.z <= z) != (b.z <= z)) xs.push_back(a.r + (z - a.z) / (b.z - a.z) * (b.r - a.r));
    }
    std::sort(xs.begin(), xs.end());
    for (std::size_t i = 0; i + 1 < xs.size(); i += 2) {
      if (xs[i + 1] - xs[i] > best_width) {
        best_width = xs[i + 1] - xs[i];
        best = {0.5 * (xs[i] + xs[i + 1]), z};
      }
    }
  }
  return best;
}

std::vector<Vec2> simplify(const std::vector<Vec2>& line, double tol) {
  if (line.size() <= 2) return line;
  const auto kept = douglas_peucker(line.size(), tol, [&](std::size_t k, std::size_t i, std::size_t j) {
    return segment_distance(line[k], line[i], line[j]);
  });
  std::vector<Vec2> out;
  for (const std::size_t k : kept) out.push_back(line[k]);
  return out;
}

}  // namespace tocd::sim::geometry::detail

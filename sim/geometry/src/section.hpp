#pragma once

// The r-z section of the composite: every surface of the optical model is either a flat box
// face or the revolution of an edge of this planar straight-line graph about the pin axis.
// Vertices are shared between the surfaces that meet there, so revolving them with one
// common set of azimuths gives conforming 3D facets.

#include <string>
#include <vector>

namespace tocd::sim::geometry::detail {

struct Vec2 {
  double r = 0, z = 0;
};

inline Vec2 operator-(Vec2 a, Vec2 b) {
  return {a.r - b.r, a.z - b.z};
}
inline Vec2 operator+(Vec2 a, Vec2 b) {
  return {a.r + b.r, a.z + b.z};
}
inline Vec2 operator*(double s, Vec2 a) {
  return {s * a.r, s * a.z};
}
inline double dot(Vec2 a, Vec2 b) {
  return a.r * b.r + a.z * b.z;
}
inline double cross(Vec2 a, Vec2 b) {
  return a.r * b.z - a.z * b.r;
}
double norm(Vec2 a);
/// Distance from p to the segment a-b, and the parameter t in [0, 1] of the closest point.
double segment_distance(Vec2 p, Vec2 a, Vec2 b, double* t = nullptr);

/// A surface of the complex: its name (used in error messages) and the boundary marker its
/// faces carry when they lie on the outside of the box (0 for internal interfaces).
struct Surface {
  std::string name;
  int boundary_marker = 0;
};

struct Section {
  struct Edge {
    int a, b;
    int surface;
  };
  std::vector<Vec2> vertices;
  std::vector<Edge> edges;
  std::vector<Surface> surfaces;

  int add_vertex(Vec2 p) {
    vertices.push_back(p);
    return static_cast<int>(vertices.size()) - 1;
  }
  int add_surface(std::string name, int marker = 0) {
    surfaces.push_back({std::move(name), marker});
    return static_cast<int>(surfaces.size()) - 1;
  }
  /// Adds edge a-b unless it is degenerate or already present (shared by two surfaces).
  void add_edge(int a, int b, int surface);
  bool has_edge(int a, int b) const;
};

/// Throws GeometryError when two edges of different or equal surfaces cross, overlap, or
/// when a vertex lies on an edge it is not an end of (closer than `tolerance_mm`); the
/// message names both surfaces and the place.
void check_section(const Section& section, double tolerance_mm);

/// Twice the signed area of a closed polygon (counter-clockwise in (r, z) positive).
double signed_area2(const std::vector<Vec2>& polygon);

/// Integral of r over a closed polygon (signed by orientation): the revolved volume is
/// 2 pi times it; an N-gon revolution has N sin(2 pi / N) times it.
double integral_r_dA(const std::vector<Vec2>& polygon);

/// A point strictly inside a simple polygon (midpoint of the widest scanline interval).
Vec2 interior_point(const std::vector<Vec2>& polygon);

/// Whether two closed segments intersect (touching included).
bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

/// Douglas-Peucker simplification of an open polyline, keeping both ends.
std::vector<Vec2> simplify(const std::vector<Vec2>& line, double tolerance_mm);

}  // namespace tocd::sim::geometry::detail

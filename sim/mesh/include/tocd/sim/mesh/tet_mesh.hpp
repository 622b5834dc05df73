#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace tocd::sim::mesh {

/// Most nodes, tets or boundary faces a mesh may have: node indices are int32, and 1e8 tets
/// already take several GB once prepared. Readers refuse larger counts before allocating.
inline constexpr std::int64_t kMaxMeshItems = 100'000'000;

/// Largest |coordinate| accepted (mm): 1 km, far beyond any sample, and small enough that
/// bounding boxes and volumes stay finite.
inline constexpr double kMaxCoordinateMm = 1e6;

/// A point in the simulator's frame, millimetres.
using Point3 = std::array<double, 3>;

/// A boundary triangle carrying a marker (e.g. "slide bottom"), as TetGen's .face file does.
struct BoundaryFace {
  std::array<std::int32_t, 3> nodes;
  std::int32_t marker = 0;
};

/// A conforming tetrahedral mesh with one region id per tetrahedron. Plain data: the
/// geometry module writes it, the Monte Carlo reads it. Node indices are 0-based.
struct TetMesh {
  std::vector<Point3> nodes;
  std::vector<std::array<std::int32_t, 4>> tets;
  std::vector<std::int32_t> regions;  ///< one per tet
  std::vector<BoundaryFace> boundary_faces;
};

/// Signed volume of a tetrahedron (mm^3): positive when (b-a, c-a, d-a) is right-handed.
double signed_volume(const Point3& a, const Point3& b, const Point3& c, const Point3& d) noexcept;

/// Signed volume of tet `t` of `mesh`.
double tet_volume(const TetMesh& mesh, std::size_t t) noexcept;

/// Sum of the volumes of the tets of `region` (all tets when region < 0), mm^3.
double region_volume(const TetMesh& mesh, std::int32_t region);

}  // namespace tocd::sim::mesh

#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "photon_rng.hpp"
#include "tocd/sim/mc/prepared_mesh.hpp"
#include "tocd/sim/mc/source.hpp"

namespace tocd::sim::mc {

/// Where and how a packet meets the mesh: on face `face` of tet `tet`, at `pos`, travelling
/// along the unit vector `dir` (still in the ambient medium). tet < 0: the beam missed.
struct Entry {
  double pos[3];
  double dir[3];
  std::int32_t tet = -1;
  std::int32_t face = 0;
};

/// Finds the first front-facing boundary face along lines of a fixed direction, with a 2-D
/// grid of the faces projected on the plane normal to that direction.
class BoundaryLocator {
 public:
  BoundaryLocator(const PreparedMesh& mesh, const std::array<double, 3>& unit_dir);
  Entry locate(const std::array<double, 3>& origin) const;

 private:
  struct Face {
    std::int32_t tet, face;
    double u[3], v[3];  // projected corners
    double normal[3], offset;
  };
  const PreparedMesh& mesh_;
  std::array<double, 3> d_{}, e1_{}, e2_{};
  std::vector<Face> faces_;
  double umin_ = 0, vmin_ = 0, hu_ = 1, hv_ = 1;
  int nu_ = 1, nv_ = 1;
  std::vector<std::size_t> start_;
  std::vector<std::int32_t> items_;
};

/// Samples entry points for a source. Validates the source at construction (throws
/// SourceError when it cannot reach the mesh).
class Launcher {
 public:
  Launcher(const PreparedMesh& mesh, const Source& source);
  Entry sample(PhotonRng& rng) const;

 private:
  const PreparedMesh& mesh_;
  Source source_;
  std::array<double, 3> dir_{}, e1_{}, e2_{};
  Entry pencil_{};
  std::vector<BoundaryLocator> locator_;  // empty or one (disk)
  struct MarkerFace {
    std::int32_t tet, face;
    double a[3], b[3], c[3];
    double inward[3];
  };
  std::vector<MarkerFace> marker_faces_;
  std::vector<double> marker_cdf_;
};

}  // namespace tocd::sim::mc

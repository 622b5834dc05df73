#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "tocd/sim/mesh/tet_mesh.hpp"

namespace tocd::sim::mesh {

/// One horizontal layer of a slab, listed from the top down.
struct SlabLayer {
  double thickness_mm = 1.0;
  std::int32_t region = 1;
  int cells_z = 4;  ///< subdivisions through the thickness
};

/// A box slab: x in [-width/2, width/2], y in [-depth/2, depth/2], z from 0 (bottom) up to the
/// sum of the layer thicknesses (top). Each grid cell is split into 6 tets around its main
/// diagonal (a conforming Kuhn triangulation), so any cells_xy / cells_z gives a valid
/// tetrahedralisation of the same slab. Boundary markers: top 1, bottom 2, sides 3.
struct SlabSpec {
  double width_mm = 10.0;
  double depth_mm = 10.0;
  std::vector<SlabLayer> layers{SlabLayer{}};
  int cells_x = 10;
  int cells_y = 10;
  /// Optional rigid rotation applied after building: axis (need not be unit) and angle about
  /// the slab's centre. Zero angle = no rotation.
  Point3 rotation_axis{1.0, 0.0, 0.0};
  double rotation_deg = 0.0;
};

/// Largest slab width, depth or layer thickness (mm): a metre is far beyond any sample.
inline constexpr double kMaxSlabMm = 1000.0;
/// Most cells across x and y (--slab-cells).
inline constexpr int kMaxSlabCellsAcross = 1000;
/// Most tets a built-in slab may have (about 1 GB once prepared for transport).
inline constexpr std::int64_t kMaxSlabTets = 10'000'000;

inline constexpr std::int32_t kSlabTopMarker = 1;
inline constexpr std::int32_t kSlabBottomMarker = 2;
inline constexpr std::int32_t kSlabSideMarker = 3;

/// Parses "WxDxT" (one layer of region 1) or "WxD:T1@R1,T2@R2,..." (layers from the top
/// down, thickness in mm @ region id), all in mm. `cells_across` sets cells_x = cells_y; each
/// layer gets about cubic cells in z (at least 2). Throws tocd::ConfigError naming the text
/// and the accepted range (lengths up to kMaxSlabMm, cells_across up to kMaxSlabCellsAcross).
SlabSpec parse_slab_spec(const std::string& text, int cells_across = 20);

/// Builds the slab. Throws tocd::ConfigError on sizes outside (0, kMaxSlabMm], cell counts
/// below 1 or a slab of more than kMaxSlabTets tets, naming the value and the limit.
TetMesh make_slab(const SlabSpec& spec);

}  // namespace tocd::sim::mesh

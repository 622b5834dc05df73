#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "tocd/core/error.hpp"
#include "tocd/sim/mesh/tet_mesh.hpp"

namespace tocd::sim::geometry {

/// The composite optical geometry cannot be built: a bad profile (non-monotonic, self-
/// intersecting, outside the skin), sizes that do not fit, or TetGen rejecting the complex.
/// The message names the surface at fault ("compressed outline 0", "skin top surface", ...).
using GeometryError = tocd::ErrorOf<struct GeometryModule, tocd::Error>;

/// A point of an r-z profile, mm (r >= 0 radial from the pin axis, z up, slide top at z = 0).
struct ProfilePoint {
  double r_mm = 0;
  double z_mm = 0;
};

/// The deformed skin in r-z, the same convention as sim/fe: skin bottom on the slide at z = 0,
/// undeformed top at z = thickness_mm.
struct SkinProfile {
  double thickness_mm = 2.5;
  /// Deformed skin top, ordered from r = 0 outwards up to some r_max; the skin is flat at
  /// z = thickness_mm beyond r_max. Empty = undeformed flat skin.
  std::vector<ProfilePoint> top_surface;
  /// Closed counter-clockwise polygons (no repeated end point) of the compressed zone; may be
  /// empty. They may run along the axis, the skin top (e.g. under the pin) and the slide.
  std::vector<std::vector<ProfilePoint>> compressed_outlines;
};

/// Region attribute of every tet.
enum Region : int { pin = 1, slide = 2, air = 3, skin = 4, compressed = 5 };

/// Boundary marker of every outer face. `top` is the air's top face around the pin; the
/// pin's own top face (where the source light enters) carries `pin_top`. The box's side
/// faces carry the marker of the layer they bound, so light lost sideways can be told apart:
/// guided in the slide, or diffused through the skin.
enum Marker : int { slide_bottom = 1, slide_sides = 2, top = 3, pin_top = 4, skin_sides = 5, air_sides = 6 };

/// Mesh size. `preset` is "fast" (0.1-0.2 M tets, for live prediction) or "paper" (0.2 mm
/// elements, ~0.5 M tets). Both presets describe the same geometry (the same r-z section
/// segments and azimuths); they differ only in tet size. A positive max_edge_mm overrides the
/// preset's element edge (and refines the section when finer than its 0.2 mm segments); a
/// positive max_volume_mm3 overrides the tet volume bound (default: derived from the edge);
/// a positive tip_edge_mm overrides the segment length of the pin's hemispherical tip and of
/// the skin under it (default 0.05 mm; never coarser than the section).
struct MeshSize {
  std::string preset = "fast";
  double max_edge_mm = 0;
  double max_volume_mm3 = 0;
  double tip_edge_mm = 0;  ///< > 0: segment length of the pin's hemispherical tip (default: preset)
};

struct CompositeSpec {
  double slide_size_mm = 12.5, slide_thickness_mm = 1.0, skin_size_mm = 12.5;
  double pin_radius_mm = 1.5, pin_length_mm = 3.3, pin_displacement_mm = 0;
  bool baseline = false;  ///< glass only: pin tip on the slide, no skin, air around
  SkinProfile skin;
  MeshSize size;
};

/// Meshed size of one region next to its volume computed independently from the
/// geometry's polygons (box volumes, Pappus' theorem with the N-gon factor for revolved
/// parts).
struct RegionStats {
  int region;
  std::size_t tets;
  double volume_mm3;
  double expected_volume_mm3;
};

/// Resolved size parameters (what a preset means), reported with the mesh.
struct ResolvedSize {
  double edge_mm = 0;          ///< target element edge (sets the default volume bound)
  double section_edge_mm = 0;  ///< geometry: segment length of the skin top, pin outline, outlines
  double tip_edge_mm = 0;      ///< geometry: segment length of the pin's tip and the skin under it
  double max_volume_mm3 = 0;   ///< TetGen volume bound ('a')
  int azimuth_segments = 0;    ///< N (geometry): every revolved surface is an N-gon prism band
  double radius_edge_ratio = 0, min_dihedral_deg = 0;  ///< TetGen quality ('q')
};

struct CompositeMesh {
  tocd::sim::mesh::TetMesh mesh;     ///< regions per tet (Region), boundary faces (Marker)
  std::vector<RegionStats> regions;  ///< one per region present, in Region order
  double seconds = 0;                ///< building + meshing wall time
  ResolvedSize size;
  std::string tetgen_switches;
  double contact_radius_mm = 0;  ///< radius of the pin/skin contact disc as meshed (0: point)
};

/// The size a MeshSize resolves to. Throws GeometryError for an unknown preset or a
/// non-positive / non-finite explicit value.
ResolvedSize resolve_size(const MeshSize& size);

/// Most tets a composite mesh may have: 10 times the paper preset's ~0.5 M. Beyond it TetGen
/// needs many GB and hours (a max edge of 1e-6 mm was still meshing after 100 s at 620 MB and
/// growing), which no requested edge length is worth.
inline constexpr double kMaxCompositeTets = 5.0e6;

/// A lower estimate of the tets a spec's mesh will have, from its sizes alone (no meshing):
/// the box's volume over the volume bound, and the surface facets of the revolved outlines
/// (each the base of at least two tets). Cheap enough to check before any work.
double estimated_tets(const CompositeSpec& spec);

/// Throws GeometryError when estimated_tets(spec) is above kMaxCompositeTets, naming the
/// sizes to change.
void check_mesh_size(const CompositeSpec& spec);

/// Builds the composite piecewise-linear complex (slide, skin with its revolved deformed top,
/// compressed zones, pin at its displaced position, air up to the pin's top face) and meshes
/// it with TetGen. Throws GeometryError naming the surface at fault, or the sizes when the
/// mesh would be too large (check_mesh_size, before anything is built).
///
/// TetGen runs in a child process (it cannot be interrupted, and Debian's libtet crashes on
/// its own error path instead of reporting): with `cancel`, the build stops with
/// tocd::Cancelled within about 20 ms of the flag being set, the child killed.
CompositeMesh build_composite(const CompositeSpec& spec, const std::atomic<bool>* cancel = nullptr);

}  // namespace tocd::sim::geometry

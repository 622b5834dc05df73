#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "tocd/core/error.hpp"
#include "tocd/sim/mesh/topology.hpp"

namespace tocd::sim::mc {

/// A source that cannot light the mesh (misses it, unknown marker, bad syntax).
using SourceError = tocd::ErrorOf<struct SourceInput>;

/// How light enters the mesh. All beams are collimated and come from the ambient medium.
/// A beam is the line through `origin` along `direction`: it enters at the first boundary
/// face facing it along that line (so the origin may lie above the mesh or on its surface).
struct Source {
  enum class Kind { pencil, disk, marker };
  Kind kind = Kind::pencil;
  std::array<double, 3> origin{0.0, 0.0, 0.0};      ///< pencil point / disk centre, mm
  std::array<double, 3> direction{0.0, 0.0, -1.0};  ///< need not be unit; pencil and disk
  double radius_mm = 0.0;                           ///< disk radius
  std::int32_t marker = 0;                          ///< marker source: faces with this marker
  /// Marker source: when false, each face is lit along its own inward normal with weight by
  /// area (a flat face lit straight on); when true, along `direction` with weight by
  /// projected area.
  bool marker_uses_direction = false;
  /// Entry specular reflection: true = the Fresnel-reflected part of each packet is tallied
  /// as `specular` and the rest enters; false = the whole packet enters (refracted).
  bool entry_specular = true;
};

/// Parses the command-line syntax, with defaults taken from the mesh's bounding box:
///   pencil                        straight down (-z) at the centre of the box top
///   pencil:X,Y                    straight down at (X, Y)
///   pencil:X,Y,Z,DX,DY,DZ         from (X, Y, Z) along (DX, DY, DZ)
///   disk:R  | disk:X,Y,R          collimated disk of radius R straight down
///   disk:X,Y,Z,DX,DY,DZ,R         disk centred at (X, Y, Z) facing (DX, DY, DZ)
///   marker:N                      faces with boundary marker N, lit along their inward normal
/// A suffix ",nospec" turns entry specular reflection off. Throws SourceError.
Source parse_source(const std::string& text, const mesh::BoundingBox& box);

/// One line describing the source, for logs and JSON.
std::string describe(const Source& source);

}  // namespace tocd::sim::mc

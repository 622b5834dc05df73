#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "tocd/sim/fe/model.hpp"

namespace tocd::sim::fe {

/// Deformed bilinear-quad mesh of the skin section (nodes in r-z, quads counter-clockwise).
struct FeMesh {
  std::vector<Point2> nodes;
  std::vector<std::array<int, 4>> quads;
  int nodes_r = 0, nodes_z = 0;  ///< structured layout: node (i, j) = j * nodes_r + i
};

class PointLocator;  // bucket grid over deformed quads (result.cpp)

struct FeStepResult {
  double displacement_mm = 0;
  double force_N = 0;  ///< pin reaction, full 360 deg (axisymmetric) or full width x depth
  /// Deformed skin top, ordered from r = 0 to r = outer radius.
  std::vector<Point2> top_surface;
  /// Outlines of the compressed region (min principal log strain <= -0.5), deformed
  /// configuration, closed (no repeated end point), outer boundaries counter-clockwise in
  /// (r, z); a hole (not met in practice) would come clockwise.
  std::vector<std::vector<Point2>> compressed_outlines;
  double compressed_log_strain = -0.5;  ///< the threshold the region was drawn with (FeModel)
  double compressed_area_mm2 = 0;
  /// Axisymmetric: revolved volume 2 pi int r dA. Plane kinematics: area x depth_mm.
  double compressed_volume_mm3 = 0;
  int newton_iterations = 0;  ///< Newton iterations spent since the previous reported step
  int load_increments = 0;    ///< accepted increments since the previous reported step
  double max_penetration_mm = 0;
  double contact_radius_mm = 0;  ///< largest deformed r of a node in contact

  FeMesh mesh;                                 ///< deformed mesh
  std::vector<Point2> displacement;            ///< per node [mm]
  std::vector<double> element_min_log_strain;  ///< min principal log strain per element (centroid)
  std::vector<double> element_J;               ///< volume ratio per element (mean dilatation)

  /// Min principal log strain of the element containing (r, z) in the deformed configuration;
  /// NaN outside the skin.
  double min_log_strain_at(double r_mm, double z_mm) const;
  /// Element index containing (r, z) (deformed), -1 outside.
  int element_at(double r_mm, double z_mm) const;

  std::shared_ptr<const PointLocator> locator;  ///< built by solve(); rebuilt on demand if null
};

struct FeResult {
  FeModel model;
  std::vector<FeStepResult> steps;  ///< one per requested displacement that was reached
  bool complete = false;
  std::string stop_reason;  ///< empty when complete
  int total_newton_iterations = 0;
  int total_load_increments = 0;
  double seconds = 0;
};

}  // namespace tocd::sim::fe

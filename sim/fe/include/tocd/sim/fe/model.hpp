#pragma once

#include <string>

#include "tocd/core/error.hpp"
#include "tocd/sim/material/ogden.hpp"

namespace tocd::sim::fe {

/// Bad model input (names the field and the value found).
using FeError = tocd::ErrorOf<struct FeModule>;

/// Coordinates r-z: r >= 0 radial (x for the plane kinematics, with a symmetry plane at
/// x = 0), z up; slide top (skin bottom) at z = 0, undeformed skin top at z = thickness_mm; the
/// pin tip starts at z = thickness_mm and sits at z = thickness_mm - d.
struct Point2 {
  double r_mm = 0, z_mm = 0;
};

enum class Kinematics { axisymmetric, plane_strain, plane_stress };
enum class Bottom { bonded, sliding };

Kinematics parse_kinematics(
    const std::string& s);                  ///< "axi" | "axisymmetric" | "plane-strain" | "plane-stress"
Bottom parse_bottom(const std::string& s);  ///< "bonded" | "sliding"
std::string to_string(Kinematics k);
std::string to_string(Bottom b);

/// Numerical controls; the defaults suit the published case and thinner skins.
struct FeSolverSettings {
  int max_newton_iterations = 25;  ///< per load increment before it is cut back
  double initial_step_mm = 0.05;   ///< first displacement increment
  double min_step_mm = 1e-5;       ///< give up (partial result) below this increment
  double max_step_mm = 0.1;        ///< largest displacement increment
  double penalty_factor = 200;     ///< contact penalty / current nodal stiffness
  /// Augmented-Lagrangian target: largest penetration as a fraction of the pin displacement.
  double penetration_tolerance = 1e-3;
  int max_augmentations = 6;         ///< multiplier updates per increment
  double residual_tolerance = 1e-8;  ///< out-of-balance force relative to the internal force scale
};

struct FeModel {
  double thickness_mm = 2.5;
  double outer_radius_mm = 6.25;  ///< lateral extent (half width for plane kinematics)
  double pin_radius_mm = 1.5;     ///< hemisphere radius = shaft radius
  Kinematics kinematics = Kinematics::axisymmetric;
  Bottom bottom = Bottom::bonded;
  tocd::sim::material::OgdenParameters material;  ///< Abaqus-form Ogden (mu_i, alpha_i, D_i)
  double mesh_refinement = 1.0;                   ///< 2.0 = twice as fine in each direction
  /// Plane kinematics only: out-of-plane depth of the section [mm]; the reported force is
  /// for the full width (both halves) times this depth.
  double depth_mm = 1.0;
  /// An element belongs to the compressed region when its minimum principal log strain is at
  /// or below this (the published threshold: -0.5).
  double compressed_log_strain = -0.5;
  FeSolverSettings solver;

  /// 2.5 mm skin, 6.25 mm radius, 1.5 mm pin, published Ogden skin, axisymmetric, bonded.
  static FeModel published_default();

  /// Throws FeError naming the bad field (non-positive sizes, bad material, no bulk modulus).
  void validate() const;
};

}  // namespace tocd::sim::fe

#pragma once

#include <array>

#include <Eigen/Core>

#include "tocd/sim/fe/model.hpp"
#include "tocd/sim/material/hyperelastic.hpp"

namespace tocd::sim::fe {

/// Reference data of one bilinear quad: 2x2 Gauss points and the centroid.
struct ElementReference {
  struct Point {
    std::array<double, 4> N{};
    std::array<std::array<double, 2>, 4> dNdX{};
    double R = 0;       ///< reference radius (axisymmetric hoop stretch r/R)
    double weight = 0;  ///< reference volume: Gauss weight x |det J| (x R for axisymmetric)
  };
  std::array<Point, 4> gauss;
  Point centroid;
  double volume = 0;  ///< sum of the Gauss weights
};

/// X: reference nodal coordinates (r, z), counter-clockwise.
ElementReference make_element_reference(const std::array<std::array<double, 2>, 4>& X, Kinematics k);

using ElementVector = Eigen::Matrix<double, 8, 1>;
using ElementMatrix = Eigen::Matrix<double, 8, 8>;

struct ElementResponse {
  double energy = 0;        ///< stored energy (per radian for axisymmetric, per unit depth otherwise)
  ElementVector force;      ///< internal nodal forces d energy / d x, dofs (r0, z0, r1, z1, ...)
  ElementMatrix stiffness;  ///< d force / d x (symmetric)
};

/// Energy, internal force and consistent tangent of one element at current nodal positions x.
/// Axisymmetric and plane strain: isochoric part at the Gauss points, volumetric part from the
/// element's mean dilatation J = v / V (locking-free, variational, symmetric tangent). Plane
/// stress: full law with the out-of-plane stretch solved for zero normal stress at each point.
/// Returns false (response unspecified) if the element is inverted or degenerate.
bool element_response(const ElementReference& ref, const std::array<std::array<double, 2>, 4>& x,
                      Kinematics k, const tocd::sim::material::HyperelasticLaw& law, bool want_stiffness,
                      ElementResponse& out);

/// Centroid principal stretches (mean dilatation applied) and the element volume ratio.
struct ElementStrain {
  tocd::sim::material::Vec3 lambda = tocd::sim::material::Vec3::Ones();
  double J = 1;
  double min_log_strain = 0;
};
bool element_strain(const ElementReference& ref, const std::array<std::array<double, 2>, 4>& x, Kinematics k,
                    const tocd::sim::material::HyperelasticLaw& law, ElementStrain& out);

}  // namespace tocd::sim::fe

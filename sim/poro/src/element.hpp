#pragma once

#include <array>

#include <Eigen/Core>

#include "tocd/sim/material/hyperelastic.hpp"
#include "tocd/sim/poro/model.hpp"

namespace tocd::sim::poro {

constexpr int kElementDofs = 22;  ///< 9 nodes x (u_x, u_y), then 4 pore pressures
using ElementVector = Eigen::Matrix<double, kElementDofs, 1>;
using ElementMatrix = Eigen::Matrix<double, kElementDofs, kElementDofs>;

/// Reference quantities of one Gauss point: shape functions, their reference gradients, the
/// reference radius and the integration weight (axisymmetric: 2 pi R dA, plane: dA x 1 mm).
struct GaussPoint {
  double N9[9], dN9dX[9][2];
  double N4[4], dN4dX[4][2];
  double R = 0, weight = 0;
};
using ElementGauss = std::array<GaussPoint, 9>;

/// 3x3 Gauss rule on the axis-aligned element box {x0, x1, y0, y1}.
ElementGauss make_element_gauss(const std::array<double, 4>& box, Kinematics k);

struct ElementPhysics {
  Kinematics kinematics;
  const tocd::sim::material::HyperelasticLaw* skeleton;
  const Permeability* permeability;
  double dt_s;
};

/// Residual of the element (momentum: internal minus nothing external; Darcy: dt times the
/// mass balance, in mm^3) at `dofs` given the previous converged `previous` dofs, and the
/// analytic tangent when `tangent` is non-null. false where the state is inadmissible
/// (J <= 0, r <= 0, J <= phi0) or not finite.
bool element_residual(const ElementGauss& gauss, const ElementPhysics& physics, const ElementVector& dofs,
                      const ElementVector& previous, ElementVector& residual, ElementMatrix* tangent);

/// Volume ratio J of the skeleton at local point (xi, eta) of an element.
double element_volume_ratio(const std::array<double, 4>& box, Kinematics k, const ElementVector& dofs,
                            double xi, double eta);

}  // namespace tocd::sim::poro

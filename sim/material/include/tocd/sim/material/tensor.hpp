#pragma once

#include <Eigen/Core>

#include "tocd/sim/material/hyperelastic.hpp"

namespace tocd::sim::material {

/// Voigt order used for symmetric 3x3 tensors: 11, 22, 33, 12, 23, 13.
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// Kirchhoff stress tau and the spatial elasticity tensor c (Voigt, 6x6) of the Lie
/// derivative L_v tau = c : d, so that for a perturbation dF with l = dF F^-1:
///   d tau = c : sym(l) + l tau + tau l^T.
struct TensorResponse {
  double psi = 0;
  Mat3 tau = Mat3::Zero();
  Mat6 c = Mat6::Zero();
};

/// Assembles tau and c from principal stretches lambda_a, orthonormal principal directions
/// (columns of n) and a principal response. When two stretches coincide (relative difference
/// below ~1e-6: F = I, the symmetry axis, the hoop-equal case) the shear coefficient
/// (tau_a lb^2 - tau_b la^2) / (la^2 - lb^2) is replaced by its limit
/// (dtau(a,a) - dtau(a,b)) / 2 - tau_a.
TensorResponse assemble_spatial(const Vec3& lambda, const Mat3& n, const PrincipalResponse& r);

/// Principal stretches and directions of F (via b = F F^T); exact 2x2 + 1 split when b is
/// block diagonal (2D and axisymmetric kinematics).
void principal_stretches(const Mat3& F, Vec3& lambda, Mat3& n);

/// Full response of a law at deformation gradient F (det F > 0 required).
TensorResponse evaluate(const HyperelasticLaw& law, const Mat3& F);

}  // namespace tocd::sim::material

#pragma once
// Kinematics of a 2D section (axisymmetric or plane) at one integration point: what the
// hyperelastic element (sim/fe) and the biphasic element (sim/poro) both need of the
// displacement shape functions. Written once so that the two elements cannot drift apart; the
// arithmetic is in the order both used before, so their results are bitwise unchanged.
#include <Eigen/Dense>

#include "tocd/sim/material/hyperelastic.hpp"
#include "tocd/sim/material/tensor.hpp"

namespace tocd::sim::material {

/// Spatial gradients of the displacement shape functions at one point of a section.
template <int Nodes>
struct SectionGradients {
  double g[Nodes][2];  ///< g_a = F^-T Grad N_a
  double h[Nodes];     ///< hoop terms N_a / r (0 on a plane section)

  /// div(e_i N_a): the divergence of node a's virtual displacement along axis i.
  double div(int a, int i) const { return i == 0 ? g[a][0] + h[a] : g[a][1]; }

  /// B: rows (rr, zz, hoop, 2 rz) of the Kirchhoff stress's work, columns (u_r, u_z) per node.
  Eigen::Matrix<double, 4, 2 * Nodes> b_matrix() const {
    Eigen::Matrix<double, 4, 2 * Nodes> B = Eigen::Matrix<double, 4, 2 * Nodes>::Zero();
    for (int a = 0; a < Nodes; ++a) {
      B(0, 2 * a) = g[a][0];
      B(2, 2 * a) = h[a];
      B(3, 2 * a) = g[a][1];
      B(1, 2 * a + 1) = g[a][1];
      B(3, 2 * a + 1) = g[a][0];
    }
    return B;
  }

  /// In-plane geometric stiffness between nodes a and b: g_a . tau . g_b.
  double geometric(int a, int b, const Mat3& tau) const {
    double G = 0;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) G += g[a][i] * tau(i, j) * g[b][j];
    return G;
  }

  /// The second variation of the volume, per unit J: div du div Du - tr(grad du grad Du) for
  /// du = e_i N_a and Du = e_k N_b.
  double volume_second_variation(int a, int i, int b, int k) const {
    double v = div(a, i) * div(b, k) - g[a][k] * g[b][i];
    if (i == 0 && k == 0) v -= h[a] * h[b];
    return v;
  }
};

/// The gradients at a point with shape functions N, reference gradients dN/dX, the inverse of
/// the in-plane deformation gradient and the current radius r (used on an axisymmetric section).
template <int Nodes, class Shape, class ShapeGradient>
SectionGradients<Nodes> section_gradients(const Shape& N, const ShapeGradient& dNdX,
                                          const Eigen::Matrix2d& Finv, bool axisymmetric, double r) {
  SectionGradients<Nodes> s;
  for (int a = 0; a < Nodes; ++a) {
    for (int i = 0; i < 2; ++i) s.g[a][i] = dNdX[a][0] * Finv(0, i) + dNdX[a][1] * Finv(1, i);
    s.h[a] = axisymmetric ? N[a] / r : 0.0;
  }
  return s;
}

/// The Voigt rows (rr, zz, hoop, rz) of the spatial tangent that a section's B matrix uses.
inline Eigen::Matrix4d section_tangent(const Mat6& c) {
  Eigen::Matrix4d C;
  for (int I = 0; I < 4; ++I)
    for (int Jv = 0; Jv < 4; ++Jv) C(I, Jv) = c(I, Jv);
  return C;
}

/// The Kirchhoff stress's components that a section's B matrix works on (rr, zz, hoop, rz).
inline Eigen::Vector4d section_stress(const Mat3& tau) {
  return {tau(0, 0), tau(1, 1), tau(2, 2), tau(0, 1)};
}

}  // namespace tocd::sim::material

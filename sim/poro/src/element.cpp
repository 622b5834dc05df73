#include "element.hpp"

#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "grid.hpp"
#include "tocd/sim/material/section_kinematics.hpp"
#include "tocd/sim/material/tensor.hpp"

namespace tocd::sim::poro {

namespace mat = tocd::sim::material;

namespace {

GaussPoint make_point(const std::array<double, 4>& box, Kinematics k, double xi, double eta, double w) {
  const Shape s = shape_at(xi, eta);
  const double hx = box[1] - box[0], hy = box[3] - box[2];
  GaussPoint p;
  for (int a = 0; a < 9; ++a) {
    p.N9[a] = s.N9[a];
    p.dN9dX[a][0] = s.dN9[a][0] * 2 / hx;
    p.dN9dX[a][1] = s.dN9[a][1] * 2 / hy;
  }
  for (int c = 0; c < 4; ++c) {
    p.N4[c] = s.N4[c];
    p.dN4dX[c][0] = s.dN4[c][0] * 2 / hx;
    p.dN4dX[c][1] = s.dN4[c][1] * 2 / hy;
  }
  p.R = box[0] + 0.5 * (1 + xi) * hx;
  const double area = w * 0.25 * hx * hy;
  p.weight = k == Kinematics::axisymmetric ? 2 * std::numbers::pi * p.R * area : area;
  return p;
}

// Kinematics at a Gauss point for the element dofs.
struct PointKinematics {
  Eigen::Matrix2d F2;
  double r = 0, F33 = 1, J = 0;
};

PointKinematics kinematics_at(const GaussPoint& p, Kinematics k, const ElementVector& dofs) {
  PointKinematics out;
  out.F2.setIdentity();
  double ur = 0;
  for (int a = 0; a < 9; ++a) {
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) out.F2(i, j) += dofs[2 * a + i] * p.dN9dX[a][j];
    ur += p.N9[a] * dofs[2 * a];
  }
  out.r = p.R + ur;
  out.F33 = k == Kinematics::axisymmetric ? out.r / p.R : 1.0;
  out.J = out.F2.determinant() * out.F33;
  return out;
}

}  // namespace

ElementGauss make_element_gauss(const std::array<double, 4>& box, Kinematics k) {
  const double g = std::sqrt(0.6);
  const double pts[3] = {-g, 0, g}, wts[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  ElementGauss out;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) out[3 * j + i] = make_point(box, k, pts[i], pts[j], wts[i] * wts[j]);
  return out;
}

bool element_residual(const ElementGauss& gauss, const ElementPhysics& physics, const ElementVector& dofs,
                      const ElementVector& previous, ElementVector& residual, ElementMatrix* tangent) {
  residual.setZero();
  if (tangent) tangent->setZero();
  const bool axi = physics.kinematics == Kinematics::axisymmetric;
  const double dt = physics.dt_s;
  for (const GaussPoint& p : gauss) {
    const PointKinematics now = kinematics_at(p, physics.kinematics, dofs);
    const PointKinematics before = kinematics_at(p, physics.kinematics, previous);
    if (!(now.J > 0) || !(now.r > 0) || !(now.F2.determinant() > 0)) return false;
    mat::Mat3 F = mat::Mat3::Zero();
    F.topLeftCorner<2, 2>() = now.F2;
    F(2, 2) = now.F33;
    const mat::TensorResponse t = mat::evaluate(*physics.skeleton, F);
    const double J = now.J, k = physics.permeability->at(J);
    if (!std::isfinite(k)) return false;
    const double dk = physics.permeability->derivative(J);
    const double w = p.weight;

    // Spatial gradients: g_a = F^-T Grad N_a (displacement), gp_c (pressure); hoop h_a = N_a / r.
    const Eigen::Matrix2d Finv = now.F2.inverse();
    const auto sg = mat::section_gradients<9>(p.N9, p.dN9dX, Finv, axi, now.r);
    double gp[4][2];
    double pressure = 0, grad_p[2] = {0, 0};
    for (int c = 0; c < 4; ++c) {
      for (int i = 0; i < 2; ++i) gp[c][i] = p.dN4dX[c][0] * Finv(0, i) + p.dN4dX[c][1] * Finv(1, i);
      pressure += p.N4[c] * dofs[18 + c];
      for (int i = 0; i < 2; ++i) grad_p[i] += gp[c][i] * dofs[18 + c];
    }

    // Momentum: effective Kirchhoff stress through B (rows rr, zz, hoop, 2 rz), water through
    // -J p div(du).
    const Eigen::Matrix<double, 4, 18> B = sg.b_matrix();
    residual.head<18>().noalias() += w * B.transpose() * mat::section_stress(t.tau);
    for (int a = 0; a < 9; ++a)
      for (int i = 0; i < 2; ++i) residual[2 * a + i] -= w * J * pressure * sg.div(a, i);
    // Darcy (times dt): N_c (J - J_n) + dt J k gp_c . grad p.
    for (int c = 0; c < 4; ++c)
      residual[18 + c] +=
          w * (p.N4[c] * (J - before.J) + dt * J * k * (gp[c][0] * grad_p[0] + gp[c][1] * grad_p[1]));

    if (!tangent) continue;
    ElementMatrix& K = *tangent;
    K.topLeftCorner<18, 18>().noalias() += w * B.transpose() * mat::section_tangent(t.c) * B;
    for (int a = 0; a < 9; ++a)
      for (int b = 0; b < 9; ++b) {
        // Geometric stiffness of the effective stress.
        const double G = sg.geometric(a, b, t.tau);
        K(2 * a, 2 * b) += w * (G + sg.h[a] * t.tau(2, 2) * sg.h[b]);
        K(2 * a + 1, 2 * b + 1) += w * G;
        // Water: d(-J p div du) = -J p [div du div Du - tr(grad du grad Du)].
        for (int i = 0; i < 2; ++i)
          for (int kk = 0; kk < 2; ++kk)
            K(2 * a + i, 2 * b + kk) += w * J * pressure * -sg.volume_second_variation(a, i, b, kk);
      }
    for (int a = 0; a < 9; ++a)
      for (int c = 0; c < 4; ++c)
        for (int i = 0; i < 2; ++i) K(2 * a + i, 18 + c) -= w * J * sg.div(a, i) * p.N4[c];
    // Darcy rows: dJ = J div(Du); d(J k) = (k + J k') dJ; d(gp) = -l^T gp with l = e_k (x) g_b.
    for (int c = 0; c < 4; ++c) {
      const double gc_dot_gradp = gp[c][0] * grad_p[0] + gp[c][1] * grad_p[1];
      for (int b = 0; b < 9; ++b)
        for (int kk = 0; kk < 2; ++kk) {
          const double dJ = J * sg.div(b, kk);
          const double gb_gc = sg.g[b][0] * gp[c][0] + sg.g[b][1] * gp[c][1];
          const double gb_gradp = sg.g[b][0] * grad_p[0] + sg.g[b][1] * grad_p[1];
          const double d_flux =
              (k + J * dk) * dJ * gc_dot_gradp - J * k * (gb_gc * grad_p[kk] + gp[c][kk] * gb_gradp);
          K(18 + c, 2 * b + kk) += w * (p.N4[c] * dJ + dt * d_flux);
        }
      for (int d = 0; d < 4; ++d)
        K(18 + c, 18 + d) += w * dt * J * k * (gp[c][0] * gp[d][0] + gp[c][1] * gp[d][1]);
    }
  }
  return residual.allFinite() && (!tangent || tangent->allFinite());
}

double element_volume_ratio(const std::array<double, 4>& box, Kinematics k, const ElementVector& dofs,
                            double xi, double eta) {
  return kinematics_at(make_point(box, k, xi, eta, 1.0), k, dofs).J;
}

}  // namespace tocd::sim::poro

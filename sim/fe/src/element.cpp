#include "tocd/sim/fe/element.hpp"

#include <cmath>

#include <Eigen/Dense>

#include "tocd/core/isa_dispatch.hpp"
#include "tocd/sim/material/section_kinematics.hpp"
#include "tocd/sim/material/tensor.hpp"

namespace tocd::sim::fe {

namespace mat = tocd::sim::material;
using Nodes = std::array<std::array<double, 2>, 4>;

namespace {

ElementReference::Point make_point(const Nodes& X, double xi, double eta, double w, Kinematics k) {
  ElementReference::Point p;
  const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
  double dNdxi[4][2];
  for (int a = 0; a < 4; ++a) {
    p.N[a] = 0.25 * (1 + sx[a] * xi) * (1 + sy[a] * eta);
    dNdxi[a][0] = 0.25 * sx[a] * (1 + sy[a] * eta);
    dNdxi[a][1] = 0.25 * sy[a] * (1 + sx[a] * xi);
  }
  Eigen::Matrix2d J0 = Eigen::Matrix2d::Zero();  // J0(i, j) = d X_i / d xi_j
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) J0(i, j) += X[a][i] * dNdxi[a][j];
  const double det = J0.determinant();
  const Eigen::Matrix2d inv = J0.inverse();
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 2; ++i) p.dNdX[a][i] = dNdxi[a][0] * inv(0, i) + dNdxi[a][1] * inv(1, i);
  for (int a = 0; a < 4; ++a) p.R += p.N[a] * X[a][0];
  p.weight = w * std::abs(det) * (k == Kinematics::axisymmetric ? p.R : 1.0);
  return p;
}

// In-plane deformation gradient F(i, j) = d x_i / d X_j at a point.
Eigen::Matrix2d in_plane_F(const ElementReference::Point& p, const Nodes& x) {
  Eigen::Matrix2d F = Eigen::Matrix2d::Zero();
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) F(i, j) += x[a][i] * p.dNdX[a][j];
  return F;
}

double current_radius(const ElementReference::Point& p, const Nodes& x) {
  double r = 0;
  for (int a = 0; a < 4; ++a) r += p.N[a] * x[a][0];
  return r;
}

mat::Mat3 embed(const Eigen::Matrix2d& F2, double F33) {
  mat::Mat3 F = mat::Mat3::Zero();
  F.topLeftCorner<2, 2>() = F2;
  F(2, 2) = F33;
  return F;
}

// Plane stress: out-of-plane stretch with zero total normal Kirchhoff stress (the law solves
// for it), and the response with that stretch condensed out (d tau_a / d x_b at tau_3 = 0, a, b
// in-plane).
bool plane_stress_response(const mat::HyperelasticLaw& law, mat::Vec3& lambda, mat::PrincipalResponse& r) {
  lambda[2] = law.plane_stress_stretch(lambda[0], lambda[1]);
  if (!(lambda[2] > 0)) return false;
  r = law.total(lambda);
  if (!(r.dtau(2, 2) > 0)) return false;
  mat::Mat3 d = mat::Mat3::Zero();
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) d(a, b) = r.dtau(a, b) - r.dtau(a, 2) * r.dtau(2, b) / r.dtau(2, 2);
  r.dtau = d;
  r.tau[2] = 0;
  return true;
}

}  // namespace

ElementReference make_element_reference(const Nodes& X, Kinematics k) {
  ElementReference ref;
  const double g = 1.0 / std::sqrt(3.0);
  const double pts[4][2] = {{-g, -g}, {g, -g}, {g, g}, {-g, g}};
  for (int q = 0; q < 4; ++q) {
    ref.gauss[q] = make_point(X, pts[q][0], pts[q][1], 1.0, k);
    ref.volume += ref.gauss[q].weight;
  }
  ref.centroid = make_point(X, 0, 0, 4.0, k);
  return ref;
}

namespace {

// The element assembly of every Newton iteration. Its fixed-size Eigen products (B^T C B)
// run in AVX2 or AVX-512 where the CPU has them: element_version has one version per ISA
// level (tocd/core/isa_dispatch.hpp), each with this body inlined.
[[gnu::always_inline]] inline bool element_body(const ElementReference& ref, const Nodes& x, Kinematics k,
                                                const mat::HyperelasticLaw& law, bool want_stiffness,
                                                ElementResponse& out) {
  out.energy = 0;
  out.force.setZero();
  if (want_stiffness) out.stiffness.setZero();
  const bool axi = k == Kinematics::axisymmetric, pstress = k == Kinematics::plane_stress;
  double v = 0;                              // current volume (mean dilatation)
  ElementVector bv = ElementVector::Zero();  // d v / d x
  ElementMatrix kv = ElementMatrix::Zero();  // d^2 v / d x^2 (without the U'' part)
  for (const auto& p : ref.gauss) {
    const Eigen::Matrix2d F2 = in_plane_F(p, x);
    const double det2 = F2.determinant();
    if (!(det2 > 0)) return false;
    const double r = axi ? current_radius(p, x) : 1.0;
    if (!(r > 0)) return false;
    const double F33 = axi ? r / p.R : 1.0;
    mat::Vec3 lambda;
    mat::Mat3 n;
    mat::principal_stretches(embed(F2, F33), lambda, n);
    mat::PrincipalResponse pr;
    if (pstress) {
      if (!plane_stress_response(law, lambda, pr)) return false;
    } else {
      pr = law.isochoric(lambda);
    }
    const mat::TensorResponse t = mat::assemble_spatial(lambda, n, pr);
    const double w = p.weight, J = det2 * F33;
    out.energy += pr.psi * w;
    // Spatial shape-function gradients g_a = F^-T dN/dX and hoop terms h_a = N_a / r.
    const auto sg = mat::section_gradients<4>(p.N, p.dNdX, F2.inverse(), axi, r);
    const Eigen::Matrix<double, 4, 8> B = sg.b_matrix();
    out.force.noalias() += w * B.transpose() * mat::section_stress(t.tau);
    if (!pstress) {
      v += J * w;
      for (int a = 0; a < 4; ++a) {
        bv[2 * a] += J * w * sg.div(a, 0);
        bv[2 * a + 1] += J * w * sg.div(a, 1);
      }
    }
    if (!want_stiffness) continue;
    out.stiffness.noalias() += w * B.transpose() * mat::section_tangent(t.c) * B;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        const double G = sg.geometric(a, b, t.tau);
        out.stiffness(2 * a, 2 * b) += w * (G + sg.h[a] * t.tau(2, 2) * sg.h[b]);
        out.stiffness(2 * a + 1, 2 * b + 1) += w * G;
        if (pstress) continue;
        // Second variation of the volume: J [div du div Du - tr(grad du grad Du)].
        for (int i = 0; i < 2; ++i)
          for (int kk = 0; kk < 2; ++kk)
            kv(2 * a + i, 2 * b + kk) += J * w * sg.volume_second_variation(a, i, b, kk);
      }
  }
  if (!pstress) {
    const double V = ref.volume, Jbar = v / V;
    if (!(Jbar > 0)) return false;
    const mat::VolumetricResponse u = law.volumetric(Jbar);
    out.energy += V * u.U;
    out.force.noalias() += u.dU * bv;
    if (want_stiffness) out.stiffness.noalias() += (u.d2U / V) * bv * bv.transpose() + u.dU * kv;
  }
  return std::isfinite(out.energy) && out.force.allFinite();
}

#if TOCD_ISA_VERSIONS
TOCD_ISA_V4 bool element_version(const ElementReference& ref, const Nodes& x, Kinematics k,
                                 const mat::HyperelasticLaw& law, bool want_stiffness, ElementResponse& out) {
  return element_body(ref, x, k, law, want_stiffness, out);
}
TOCD_ISA_V3 bool element_version(const ElementReference& ref, const Nodes& x, Kinematics k,
                                 const mat::HyperelasticLaw& law, bool want_stiffness, ElementResponse& out) {
  return element_body(ref, x, k, law, want_stiffness, out);
}
#endif
TOCD_ISA_BASE bool element_version(const ElementReference& ref, const Nodes& x, Kinematics k,
                                   const mat::HyperelasticLaw& law, bool want_stiffness,
                                   ElementResponse& out) {
  return element_body(ref, x, k, law, want_stiffness, out);
}

}  // namespace

bool element_response(const ElementReference& ref, const Nodes& x, Kinematics k,
                      const mat::HyperelasticLaw& law, bool want_stiffness, ElementResponse& out) {
  return element_version(ref, x, k, law, want_stiffness, out);
}

bool element_strain(const ElementReference& ref, const Nodes& x, Kinematics k,
                    const mat::HyperelasticLaw& law, ElementStrain& out) {
  const bool axi = k == Kinematics::axisymmetric;
  const auto& p = ref.centroid;
  Eigen::Matrix2d F2 = in_plane_F(p, x);
  const double det2 = F2.determinant();
  const double r = axi ? current_radius(p, x) : 1.0;
  if (!(det2 > 0) || !(r > 0)) return false;
  double F33 = axi ? r / p.R : 1.0;
  mat::Vec3 lambda;
  mat::Mat3 n;
  if (k == Kinematics::plane_stress) {
    mat::principal_stretches(embed(F2, 1.0), lambda, n);
    mat::PrincipalResponse pr;
    if (!plane_stress_response(law, lambda, pr)) return false;
    out.J = lambda.prod();
  } else {
    double v = 0;  // mean dilatation of the element, as used by the stiffness
    for (const auto& q : ref.gauss) {
      const double Jq = in_plane_F(q, x).determinant() * (axi ? current_radius(q, x) / q.R : 1.0);
      v += Jq * q.weight;
    }
    out.J = v / ref.volume;
    const double Jc = det2 * F33;
    if (axi) {
      const double s = std::cbrt(out.J / Jc);
      F2 *= s;
      F33 *= s;
    } else {
      F2 *= std::sqrt(out.J / Jc);
    }
    mat::principal_stretches(embed(F2, F33), lambda, n);
  }
  out.lambda = lambda;
  out.min_log_strain = std::log(lambda.minCoeff());
  return true;
}

}  // namespace tocd::sim::fe

#include "tocd/sim/material/tensor.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace tocd::sim::material {

namespace {
constexpr int kVoigt[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
// Below this relative difference of squared stretches the shear coefficient uses its limit:
// the quotient loses ~eps/tol of its digits, the limit is off by O(tol).
constexpr double kCoincident = 1e-6;
}  // namespace

TensorResponse assemble_spatial(const Vec3& lambda, const Mat3& n, const PrincipalResponse& r) {
  TensorResponse out;
  out.psi = r.psi;
  for (int a = 0; a < 3; ++a) out.tau += r.tau[a] * n.col(a) * n.col(a).transpose();
  // c = sum_ab (dtau_ab - 2 tau_a delta_ab) N_a (x) N_b
  //   + sum_{a != b} g_ab (n_a n_b n_a n_b + n_a n_b n_b n_a),
  // g_ab = (tau_a lb^2 - tau_b la^2) / (la^2 - lb^2).
  double g[3][3] = {};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      if (a == b) continue;
      const double la2 = lambda[a] * lambda[a], lb2 = lambda[b] * lambda[b];
      if (std::abs(la2 - lb2) <= kCoincident * std::max(la2, lb2))
        g[a][b] = 0.5 * (r.dtau(a, a) - r.dtau(a, b)) - r.tau[a];
      else
        g[a][b] = (r.tau[a] * lb2 - r.tau[b] * la2) / (la2 - lb2);
    }
  for (int I = 0; I < 6; ++I)
    for (int Jv = I; Jv < 6; ++Jv) {
      const int i = kVoigt[I][0], j = kVoigt[I][1], k = kVoigt[Jv][0], l = kVoigt[Jv][1];
      double v = 0;
      for (int a = 0; a < 3; ++a) {
        const double naa = n(i, a) * n(j, a);
        for (int b = 0; b < 3; ++b) {
          const double coef = r.dtau(a, b) - (a == b ? 2 * r.tau[a] : 0.0);
          v += coef * naa * n(k, b) * n(l, b);
          if (a != b) v += g[a][b] * n(i, a) * n(j, b) * (n(k, a) * n(l, b) + n(k, b) * n(l, a));
        }
      }
      out.c(I, Jv) = out.c(Jv, I) = v;
    }
  return out;
}

void principal_stretches(const Mat3& F, Vec3& lambda, Mat3& n) {
  const Mat3 b = F * F.transpose();
  if (b(0, 2) == 0.0 && b(1, 2) == 0.0) {
    // In-plane 2x2 block + out-of-plane principal direction (2D / axisymmetric kinematics).
    const double a = b(0, 0), c = b(0, 1), d = b(1, 1);
    const double m = 0.5 * (a + d), h = 0.5 * (a - d), rad = std::hypot(h, c);
    const double e1 = m + rad;
    const double det2 = F(0, 0) * F(1, 1) - F(0, 1) * F(1, 0);
    const double e2 = det2 * det2 / e1;  // avoids cancellation in m - rad
    const double th = 0.5 * std::atan2(c, h);
    const double cs = std::cos(th), sn = std::sin(th);
    n.setZero();
    n(0, 0) = cs;
    n(1, 0) = sn;
    n(0, 1) = -sn;
    n(1, 1) = cs;
    n(2, 2) = 1.0;
    lambda = Vec3(std::sqrt(e1), std::sqrt(e2), std::sqrt(b(2, 2)));
    return;
  }
  Eigen::SelfAdjointEigenSolver<Mat3> es(b);
  lambda = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  n = es.eigenvectors();
}

TensorResponse evaluate(const HyperelasticLaw& law, const Mat3& F) {
  Vec3 lambda;
  Mat3 n;
  principal_stretches(F, lambda, n);
  return assemble_spatial(lambda, n, law.total(lambda));
}

}  // namespace tocd::sim::material

#pragma once
// Linear-elastic reference for a rigid sphere pressed into an elastic layer of thickness h on a
// rigid base (bonded, or frictionless = sliding), solved to quadrature accuracy instead of
// taken from a truncated series.
//
// Method (Lebedev-Ufliand reduction): the contact pressure is written through an auxiliary
// function phi(t) on 0 <= t <= a, p's Hankel transform being P(xi) = int_0^a phi(t) cos(xi t) dt.
// The layer's surface compliance differs from the half-space one by a factor L(xi h) per
// wavenumber, so applying Abel's operator to the surface-displacement condition under the
// indenter gives a Fredholm equation of the second kind,
//   phi(t) + int_0^a K(t, s) phi(s) ds = (E*/pi) (delta - shape(t)),
//   K(t, s) = (1/pi) int_0^inf (L(xi h) - 1) [cos xi(t - s) + cos xi(t + s)] dxi,
// with shape(t) = (t/2) ln((R + t)/(R - t)) for a sphere (t^2/R for a paraboloid). The depth
// delta follows from a smooth contact edge, phi(a) = 0, and the force is F = 2 pi int phi dt.
// For h -> inf (L = 1) this is Sneddon's sphere solution exactly.
//
// L(u) is computed, not quoted: the plane Airy stress function f(z) cos(kx) with
// f = (A + Bz) cosh kz + (C + Dz) sinh kz, unit normal surface load, no surface shear, and
// w = 0 plus u = 0 (bonded) or zero shear (frictionless) at z = h. The test checks it against
// the known closed forms for nu = 1/2.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace layer_reference {

/// Surface compliance of the layer at wavenumber k relative to a half-space, u = k h.
inline double compliance_ratio(double u, double nu, bool bonded) {
  if (u > 25.0) return 1.0;  // the base is invisible: 1 - L ~ u e^(-2u) < 1e-20
  // Values and first three derivatives (k = 1) of cosh z, z cosh z, sinh z, z sinh z.
  auto basis = [](double z) {
    const double c = std::cosh(z), s = std::sinh(z);
    return std::array<std::array<double, 4>, 4>{{{c, s, c, s},
                                                 {z * c, c + z * s, 2 * s + z * c, 3 * c + z * s},
                                                 {s, c, s, c},
                                                 {z * s, s + z * c, 2 * c + z * s, 3 * s + z * c}}};
  };
  const auto top = basis(0.0), base = basis(u);
  // Stresses: sigma_zz = -k^2 f cos, sigma_xz = k f' sin. Displacements (plane strain):
  // u_x ~ (1 - nu) f'' + nu k^2 f, u_z ~ (1 - nu) f''' + (nu - 2) k^2 f'.
  double m[4][5];
  for (int i = 0; i < 4; ++i) {
    m[0][i] = top[i][0];                                                      // f(0) = 1: unit load
    m[1][i] = top[i][1];                                                      // no shear on top
    m[2][i] = (1 - nu) * base[i][3] + (nu - 2) * base[i][1];                  // u_z = 0 at the base
    m[3][i] = bonded ? (1 - nu) * base[i][2] + nu * base[i][0] : base[i][1];  // u_x = 0 or no shear
  }
  m[0][4] = 1.0;
  m[1][4] = m[2][4] = m[3][4] = 0.0;
  for (int c = 0; c < 4; ++c) {  // Gauss-Jordan with partial pivoting
    int p = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(m[r][c]) > std::abs(m[p][c])) p = r;
    for (int j = 0; j < 5; ++j) std::swap(m[c][j], m[p][j]);
    for (int r = 0; r < 4; ++r) {
      if (r == c) continue;
      const double f = m[r][c] / m[c][c];
      for (int j = c; j < 5; ++j) m[r][j] -= f * m[c][j];
    }
  }
  double f3 = 0.0;  // f'''(0)
  for (int i = 0; i < 4; ++i) f3 += m[i][4] / m[i][i] * top[i][3];
  // Surface u_z = (1 - nu) f'''(0) / (2 mu k^2); the half-space's is (1 - nu) / (mu k).
  return 0.5 * f3;
}

struct Quadrature {
  std::vector<double> x, w;
};

/// n-point Gauss-Legendre rule on [0, 1].
inline Quadrature gauss_legendre_01(int n) {
  Quadrature q;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-15) break;
    }
    q.x.push_back(0.5 * (x + 1));
    q.w.push_back(1.0 / ((1 - x * x) * dp * dp));
  }
  return q;
}

struct Contact {
  double depth_mm, force;
};

class SphereOnLayer {
 public:
  /// E in force/mm^2 (e.g. MPa -> N), R sphere radius, h layer thickness.
  SphereOnLayer(double E, double nu, double R, double h, bool bonded, int nodes = 24)
      : estar_(E / (1 - nu * nu)), R_(R), h_(h), nodes_(gauss_legendre_01(nodes)) {
    // (L(u) - 1) sampled once on [0, 30] with 8-point panels of width 0.25; the integrand
    // decays like u e^(-2u), so the truncation is below 1e-20.
    const Quadrature panel = gauss_legendre_01(8);
    for (int p = 0; p < 120; ++p)
      for (int i = 0; i < 8; ++i) {
        u_.push_back(0.25 * (p + panel.x[i]));
        weight_.push_back(0.25 * panel.w[i] * (compliance_ratio(u_.back(), nu, bonded) - 1.0));
      }
  }

  /// Depth and force for contact radius a.
  Contact at_contact_radius(double a) const {
    const double pi = std::numbers::pi, lam = a / h_;
    const std::size_t n = nodes_.x.size();
    auto kc = [&](double x) {
      double s = 0.0;
      for (std::size_t i = 0; i < u_.size(); ++i) s += weight_[i] * std::cos(u_[i] * x);
      return s;
    };
    auto kernel = [&](double t, double s) { return lam / pi * (kc(lam * (t - s)) + kc(lam * (t + s))); };
    auto shape = [&](double t) {
      const double r = a * t;
      return 0.5 * r * std::log((R_ + r) / (R_ - r));
    };
    // Nystrom: (I + K W) phi = rhs, for rhs 1 (the depth term) and shape(t).
    std::vector<double> m(n * n), one(n, 1.0), sh(n);
    for (std::size_t i = 0; i < n; ++i) {
      sh[i] = shape(nodes_.x[i]);
      for (std::size_t j = 0; j < n; ++j)
        m[i * n + j] = (i == j) + kernel(nodes_.x[i], nodes_.x[j]) * nodes_.w[j];
    }
    for (std::size_t c = 0; c < n; ++c)  // diagonally dominant: no pivoting needed
      for (std::size_t r = c + 1; r < n; ++r) {
        const double f = m[r * n + c] / m[c * n + c];
        for (std::size_t j = c; j < n; ++j) m[r * n + j] -= f * m[c * n + j];
        one[r] -= f * one[c];
        sh[r] -= f * sh[c];
      }
    for (std::size_t c = n; c-- > 0;) {
      for (std::size_t j = c + 1; j < n; ++j) {
        one[c] -= m[c * n + j] * one[j];
        sh[c] -= m[c * n + j] * sh[j];
      }
      one[c] /= m[c * n + c];
      sh[c] /= m[c * n + c];
    }
    // phi(1) by the Nystrom interpolant; phi(1) = 0 fixes the depth.
    double one_edge = 1.0, sh_edge = shape(1.0);
    for (std::size_t j = 0; j < n; ++j) {
      const double k = kernel(1.0, nodes_.x[j]) * nodes_.w[j];
      one_edge -= k * one[j];
      sh_edge -= k * sh[j];
    }
    const double depth = sh_edge / one_edge;
    double integral = 0.0;
    for (std::size_t j = 0; j < n; ++j) integral += nodes_.w[j] * (depth * one[j] - sh[j]);
    return {depth, 2.0 * a * estar_ * integral};
  }

  /// Force at indentation depth d (secant iteration on the contact radius).
  double force_at_depth(double d) const {
    if (!(d > 0.0)) throw std::invalid_argument("layer reference: depth must be positive");
    double a0 = 0.9 * std::sqrt(R_ * d), a1 = std::sqrt(R_ * d);
    double r0 = at_contact_radius(a0).depth_mm - d;
    for (int it = 0; it < 50; ++it) {
      const Contact c = at_contact_radius(a1);
      const double r1 = c.depth_mm - d;
      if (std::abs(r1) < 1e-12 * d) return c.force;
      const double a2 = std::clamp(a1 - r1 * (a1 - a0) / (r1 - r0), 0.5 * a1, std::min(1.5 * a1, 0.999 * R_));
      a0 = a1;
      r0 = r1;
      a1 = a2;
    }
    throw std::runtime_error("layer reference: contact radius iteration did not converge");
  }

 private:
  double estar_, R_, h_;
  Quadrature nodes_;
  std::vector<double> u_, weight_;
};

}  // namespace layer_reference

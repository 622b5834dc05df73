#include "grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace tocd::sim::poro {

namespace {

// Element boundaries 0 = b_0 < ... < b_n = length, sizes growing by a constant factor so that
// the last is `grading` times the first; mid-side nodes sit half way (straight-sided elements).
std::vector<double> node_lines(double length, int n, double grading) {
  const double q = n > 1 ? std::pow(grading, 1.0 / (n - 1)) : 1.0;
  std::vector<double> b(n + 1, 0.0);
  double size = 1;
  for (int e = 0; e < n; ++e, size *= q) b[e + 1] = b[e] + size;
  for (auto& v : b) v *= length / b[n];
  std::vector<double> lines(2 * n + 1);
  for (int e = 0; e < n; ++e) {
    lines[2 * e] = b[e];
    lines[2 * e + 1] = 0.5 * (b[e] + b[e + 1]);
  }
  lines[2 * n] = length;
  return lines;
}

void quadratic(double s, double N[3], double dN[3]) {
  N[0] = 0.5 * s * (s - 1);
  N[1] = 1 - s * s;
  N[2] = 0.5 * s * (s + 1);
  dN[0] = s - 0.5;
  dN[1] = -2 * s;
  dN[2] = s + 0.5;
}

// The tensor product of two 1D Lagrange bases of K nodes each (node li along xi and lj along
// eta is node K lj + li) and its derivatives in xi and eta: the Q9 and the Q4 of shape_at.
template <std::size_t K>
void tensor_product(const double (&Nx)[K], const double (&dNx)[K], const double (&Ny)[K],
                    const double (&dNy)[K], double (&N)[K * K], double (&dN)[K * K][2]) {
  for (std::size_t lj = 0; lj < K; ++lj)
    for (std::size_t li = 0; li < K; ++li) {
      const std::size_t a = K * lj + li;
      N[a] = Nx[li] * Ny[lj];
      dN[a][0] = dNx[li] * Ny[lj];
      dN[a][1] = Nx[li] * dNy[lj];
    }
}

}  // namespace

Grid make_grid(const RectangleMesh& mesh) {
  Grid g;
  g.nx = mesh.nx;
  g.ny = mesh.ny;
  g.xs = node_lines(mesh.width_mm, mesh.nx, 1.0);
  g.ys = node_lines(mesh.height_mm, mesh.ny, mesh.row_grading);
  return g;
}

std::array<int, 9> Grid::element_nodes(int e) const {
  const int ex = e % nx, ey = e / nx;
  std::array<int, 9> n{};
  for (int lj = 0; lj < 3; ++lj)
    for (int li = 0; li < 3; ++li) n[3 * lj + li] = node(2 * ex + li, 2 * ey + lj);
  return n;
}

std::array<int, 4> Grid::element_pressure_nodes(int e) const {
  const int ex = e % nx, ey = e / nx;
  std::array<int, 4> n{};
  for (int lj = 0; lj < 2; ++lj)
    for (int li = 0; li < 2; ++li) n[2 * lj + li] = pressure_node(ex + li, ey + lj);
  return n;
}

std::array<double, 4> Grid::element_box(int e) const {
  const int ex = e % nx, ey = e / nx;
  return {xs[2 * ex], xs[2 * ex + 2], ys[2 * ey], ys[2 * ey + 2]};
}

int Grid::locate(double x, double y, double& xi, double& eta) const {
  const double tol = 1e-12 * (xs.back() + ys.back());
  if (!(x >= -tol && x <= xs.back() + tol && y >= -tol && y <= ys.back() + tol)) return -1;
  auto element_of = [](const std::vector<double>& lines, double v) {
    const int n = static_cast<int>(lines.size() - 1) / 2;
    int e = 0;
    while (e < n - 1 && v > lines[2 * e + 2]) ++e;
    return e;
  };
  const int ex = element_of(xs, x), ey = element_of(ys, y);
  const int e = ey * nx + ex;
  const auto b = element_box(e);
  xi = std::clamp(2 * (x - b[0]) / (b[1] - b[0]) - 1, -1.0, 1.0);
  eta = std::clamp(2 * (y - b[2]) / (b[3] - b[2]) - 1, -1.0, 1.0);
  return e;
}

Shape shape_at(double xi, double eta) {
  Shape s;
  double Nx[3], dNx[3], Ny[3], dNy[3];
  quadratic(xi, Nx, dNx);
  quadratic(eta, Ny, dNy);
  tensor_product(Nx, dNx, Ny, dNy, s.N9, s.dN9);
  const double Lx[2] = {0.5 * (1 - xi), 0.5 * (1 + xi)}, Ly[2] = {0.5 * (1 - eta), 0.5 * (1 + eta)};
  const double dL[2] = {-0.5, 0.5};
  tensor_product(Lx, dL, Ly, dL, s.N4, s.dN4);
  return s;
}

}  // namespace tocd::sim::poro

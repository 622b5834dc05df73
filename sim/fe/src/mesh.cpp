#include "mesh.hpp"

#include <algorithm>
#include <cmath>

namespace tocd::sim::fe {

std::vector<double> graded_grid(double length, int cells, double last_over_first) {
  std::vector<double> x(cells + 1, 0.0);
  const double q = cells > 1 ? std::pow(last_over_first, 1.0 / (cells - 1)) : 1.0;
  double sum = 0, s = 1;
  for (int k = 0; k < cells; ++k, s *= q) sum += s;
  s = length / sum;
  for (int k = 0; k < cells; ++k, s *= q) x[k + 1] = x[k] + s;
  x[cells] = length;
  return x;
}

FeMesh make_reference_mesh(const FeModel& model) {
  const double f = model.mesh_refinement;
  const double r_fine = std::min(1.3 * model.pin_radius_mm, 0.6 * model.outer_radius_mm);
  const int n_fine = std::max(4, static_cast<int>(std::lround(32 * f)));
  const int n_out = std::max(2, static_cast<int>(std::lround(14 * f)));
  const int n_z = std::max(4, static_cast<int>(std::lround(20 * f)));
  std::vector<double> r(n_fine + 1);
  for (int i = 0; i <= n_fine; ++i) r[i] = r_fine * i / n_fine;
  // Outer columns: geometric growth starting from the fine size (ratio found by bisection).
  const double dr = r_fine / n_fine, L = model.outer_radius_mm - r_fine;
  double lo = 0.5, hi = 3.0;
  for (int it = 0; it < 100; ++it) {
    const double q = 0.5 * (lo + hi);
    double sum = 0, s = dr * q;
    for (int k = 0; k < n_out; ++k, s *= q) sum += s;
    (sum > L ? hi : lo) = q;
  }
  const double q = 0.5 * (lo + hi);
  double s = dr * q;
  for (int k = 0; k < n_out; ++k, s *= q) r.push_back(r.back() + s);
  r.back() = model.outer_radius_mm;
  // Rows: top cell 2.5 times thinner than the bottom one.
  const std::vector<double> zb = graded_grid(model.thickness_mm, n_z, 1 / 2.5);

  FeMesh m;
  m.nodes_r = static_cast<int>(r.size());
  m.nodes_z = static_cast<int>(zb.size());
  for (int j = 0; j < m.nodes_z; ++j)
    for (int i = 0; i < m.nodes_r; ++i) m.nodes.push_back({r[i], zb[j]});
  for (int j = 0; j + 1 < m.nodes_z; ++j)
    for (int i = 0; i + 1 < m.nodes_r; ++i) {
      const int n0 = j * m.nodes_r + i;
      m.quads.push_back({n0, n0 + 1, n0 + 1 + m.nodes_r, n0 + m.nodes_r});
    }
  return m;
}

}  // namespace tocd::sim::fe

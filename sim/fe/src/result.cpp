#include "tocd/sim/fe/result.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tocd/sim/fe/locator.hpp"

namespace tocd::sim::fe {

PointLocator::PointLocator(const FeMesh& mesh) : mesh_(mesh) {
  if (mesh_.quads.empty()) return;
  double r1 = -1e300, z1 = -1e300;
  r0_ = z0_ = 1e300;
  for (const auto& p : mesh_.nodes) {
    r0_ = std::min(r0_, p.r_mm);
    z0_ = std::min(z0_, p.z_mm);
    r1 = std::max(r1, p.r_mm);
    z1 = std::max(z1, p.z_mm);
  }
  const double cells = std::sqrt(static_cast<double>(mesh_.quads.size()));
  nr_ = nz_ = std::max(1, static_cast<int>(cells));
  dr_ = std::max((r1 - r0_) / nr_, 1e-12);
  dz_ = std::max((z1 - z0_) / nz_, 1e-12);
  buckets_.resize(static_cast<std::size_t>(nr_) * nz_);
  for (std::size_t e = 0; e < mesh_.quads.size(); ++e) {
    double a0 = 1e300, a1 = -1e300, b0 = 1e300, b1 = -1e300;
    for (int n : mesh_.quads[e]) {
      a0 = std::min(a0, mesh_.nodes[n].r_mm);
      a1 = std::max(a1, mesh_.nodes[n].r_mm);
      b0 = std::min(b0, mesh_.nodes[n].z_mm);
      b1 = std::max(b1, mesh_.nodes[n].z_mm);
    }
    const int i0 = std::clamp(static_cast<int>((a0 - r0_) / dr_), 0, nr_ - 1);
    const int i1 = std::clamp(static_cast<int>((a1 - r0_) / dr_), 0, nr_ - 1);
    const int j0 = std::clamp(static_cast<int>((b0 - z0_) / dz_), 0, nz_ - 1);
    const int j1 = std::clamp(static_cast<int>((b1 - z0_) / dz_), 0, nz_ - 1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        buckets_[static_cast<std::size_t>(j) * nr_ + i].push_back(static_cast<int>(e));
  }
}

int PointLocator::find(double r, double z) const {
  if (buckets_.empty()) return -1;
  const double fi = (r - r0_) / dr_, fj = (z - z0_) / dz_;
  if (fi < -1e-9 || fj < -1e-9 || fi > nr_ + 1e-9 || fj > nz_ + 1e-9) return -1;
  const int i = std::clamp(static_cast<int>(fi), 0, nr_ - 1),
            j = std::clamp(static_cast<int>(fj), 0, nz_ - 1);
  for (int e : buckets_[static_cast<std::size_t>(j) * nr_ + i]) {
    const auto& q = mesh_.quads[e];
    // Crossing-number test on the quad's polygon (edges on the boundary count as inside
    // for one of the two neighbours).
    bool inside = false;
    for (int k = 0; k < 4; ++k) {
      const Point2& a = mesh_.nodes[q[k]];
      const Point2& b = mesh_.nodes[q[(k + 1) % 4]];
      if ((a.z_mm > z) != (b.z_mm > z)) {
        const double rc = a.r_mm + (z - a.z_mm) * (b.r_mm - a.r_mm) / (b.z_mm - a.z_mm);
        if (r < rc) inside = !inside;
      }
    }
    if (inside) return e;
  }
  return -1;
}

int FeStepResult::element_at(double r_mm, double z_mm) const {
  if (!locator) return PointLocator(mesh).find(r_mm, z_mm);
  return locator->find(r_mm, z_mm);
}

double FeStepResult::min_log_strain_at(double r_mm, double z_mm) const {
  const int e = element_at(r_mm, z_mm);
  return e < 0 ? std::numeric_limits<double>::quiet_NaN()
               : element_min_log_strain[static_cast<std::size_t>(e)];
}

}  // namespace tocd::sim::fe

#include "launcher.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "tocd/sim/mesh/cell_buckets.hpp"

namespace tocd::sim::mc {
namespace {

using V3 = std::array<double, 3>;
double dot(const V3& a, const V3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
V3 normalised(V3 a) {
  const double n = std::sqrt(dot(a, a));
  if (!(n > 0.0) || !std::isfinite(n)) throw SourceError("source direction must be a non-zero finite vector");
  return {a[0] / n, a[1] / n, a[2] / n};
}
// Two unit vectors completing d to an orthonormal frame.
void frame(const V3& d, V3& e1, V3& e2) {
  const V3 helper = std::abs(d[0]) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0};
  e1 = normalised(cross(d, helper));
  e2 = cross(d, e1);
}
// Node `local` of kernel tet `tet` (kernel records keep the input tet's local numbering).
V3 node(const PreparedMesh& m, std::int32_t tet, int local) {
  return m.mesh
      .nodes[m.mesh.tets[static_cast<std::size_t>(m.original_of[static_cast<std::size_t>(tet)])][local]];
}

}  // namespace

BoundaryLocator::BoundaryLocator(const PreparedMesh& mesh, const V3& unit_dir) : mesh_(mesh), d_(unit_dir) {
  frame(d_, e1_, e2_);
  umin_ = vmin_ = HUGE_VAL;
  double umax = -HUGE_VAL, vmax = -HUGE_VAL;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const KernelLink& link = mesh.links[t];
    if (link.next[0] >= 0 && link.next[1] >= 0 && link.next[2] >= 0 && link.next[3] >= 0) continue;
    const auto planes = mesh::face_planes(mesh.mesh, static_cast<std::size_t>(mesh.original_of[t]));
    for (int f = 0; f < 4; ++f) {
      if (link.next[f] >= 0 || dot(planes[f].normal, d_) > -1e-12) continue;
      Face face{static_cast<std::int32_t>(t), f, {}, {}, {}, planes[f].offset};
      std::copy(planes[f].normal.begin(), planes[f].normal.end(), face.normal);
      for (int v = 0; v < 3; ++v) {
        const V3 p = node(mesh, face.tet, mesh::kFaceLocalNodes[f][v]);
        face.u[v] = dot(p, e1_);
        face.v[v] = dot(p, e2_);
        umin_ = std::min(umin_, face.u[v]);
        umax = std::max(umax, face.u[v]);
        vmin_ = std::min(vmin_, face.v[v]);
        vmax = std::max(vmax, face.v[v]);
      }
      faces_.push_back(face);
    }
  }
  if (faces_.empty()) return;
  const int n = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(faces_.size()))), 1, 1024);
  nu_ = nv_ = n;
  hu_ = std::max(umax - umin_, 1e-300) / nu_;
  hv_ = std::max(vmax - vmin_, 1e-300) / nv_;
  auto cells = [&](const Face& f, int& i0, int& i1, int& j0, int& j1) {
    i0 = std::clamp(static_cast<int>((*std::min_element(f.u, f.u + 3) - umin_) / hu_), 0, nu_ - 1);
    i1 = std::clamp(static_cast<int>((*std::max_element(f.u, f.u + 3) - umin_) / hu_), 0, nu_ - 1);
    j0 = std::clamp(static_cast<int>((*std::min_element(f.v, f.v + 3) - vmin_) / hv_), 0, nv_ - 1);
    j1 = std::clamp(static_cast<int>((*std::max_element(f.v, f.v + 3) - vmin_) / hv_), 0, nv_ - 1);
  };
  auto buckets = mesh::bucket_by_cell(faces_.size(), static_cast<std::size_t>(nu_) * nv_,
                                      [&](std::size_t k, const auto& add) {
                                        int i0, i1, j0, j1;
                                        cells(faces_[k], i0, i1, j0, j1);
                                        for (int j = j0; j <= j1; ++j)
                                          for (int i = i0; i <= i1; ++i)
                                            add(static_cast<std::size_t>(j) * nu_ + i);
                                      });
  start_ = std::move(buckets.start);
  items_ = std::move(buckets.items);
}

Entry BoundaryLocator::locate(const V3& o) const {
  Entry best;
  if (faces_.empty()) return best;
  const double pu = dot(o, e1_), pv = dot(o, e2_);
  const double gu = (pu - umin_) / hu_, gv = (pv - vmin_) / hv_;
  if (gu < -1e-9 || gv < -1e-9 || gu > nu_ + 1e-9 || gv > nv_ + 1e-9) return best;
  const int i = std::clamp(static_cast<int>(gu), 0, nu_ - 1),
            j = std::clamp(static_cast<int>(gv), 0, nv_ - 1);
  const std::size_t c = static_cast<std::size_t>(j) * nu_ + i;
  double best_s = HUGE_VAL;
  for (std::size_t k = start_[c]; k < start_[c + 1]; ++k) {
    const Face& f = faces_[static_cast<std::size_t>(items_[k])];
    // Barycentric coordinates in the projection; a small tolerance keeps points on shared
    // edges inside at least one face.
    const double det = (f.u[1] - f.u[0]) * (f.v[2] - f.v[0]) - (f.u[2] - f.u[0]) * (f.v[1] - f.v[0]);
    const double b1 = ((pu - f.u[0]) * (f.v[2] - f.v[0]) - (f.u[2] - f.u[0]) * (pv - f.v[0])) / det;
    const double b2 = ((f.u[1] - f.u[0]) * (pv - f.v[0]) - (pu - f.u[0]) * (f.v[1] - f.v[0])) / det;
    constexpr double kTol = 1e-12;
    if (b1 < -kTol || b2 < -kTol || b1 + b2 > 1.0 + kTol) continue;
    const double nd = f.normal[0] * d_[0] + f.normal[1] * d_[1] + f.normal[2] * d_[2];
    const double s = (f.offset - (f.normal[0] * o[0] + f.normal[1] * o[1] + f.normal[2] * o[2])) / nd;
    if (s < best_s) {
      best_s = s;
      best.tet = f.tet;
      best.face = f.face;
    }
  }
  if (best.tet >= 0) {
    for (int k = 0; k < 3; ++k) {
      best.pos[k] = o[k] + best_s * d_[k];
      best.dir[k] = d_[k];
    }
  }
  return best;
}

Launcher::Launcher(const PreparedMesh& mesh, const Source& source) : mesh_(mesh), source_(source) {
  if (source.kind != Source::Kind::marker || source.marker_uses_direction) {
    dir_ = normalised(source.direction);
    frame(dir_, e1_, e2_);
  }
  switch (source.kind) {
    case Source::Kind::pencil: {
      pencil_ = BoundaryLocator(mesh, dir_).locate(source.origin);
      if (pencil_.tet < 0) {
        throw SourceError(
            fmt::format("source outside the mesh: the pencil beam through ({}, {}, {}) along ({}, {}, {}) "
                        "does not meet it",
                        source.origin[0], source.origin[1], source.origin[2], dir_[0], dir_[1], dir_[2]));
      }
      break;
    }
    case Source::Kind::disk: {
      if (!(source.radius_mm > 0.0))
        throw SourceError(fmt::format("disk radius {} mm must be > 0", source.radius_mm));
      locator_.emplace_back(mesh, dir_);
      if (locator_.front().locate(source.origin).tet < 0) {
        throw SourceError(
            fmt::format("source outside the mesh: the disk centred at ({}, {}, {}) does not face it",
                        source.origin[0], source.origin[1], source.origin[2]));
      }
      break;
    }
    case Source::Kind::marker: {
      double total = 0.0;
      for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
        const KernelLink& link = mesh.links[t];
        for (int f = 0; f < 4; ++f) {
          if (link.next[f] >= 0 ||
              mesh.groups[static_cast<std::size_t>(-1 - link.next[f])].marker != source.marker) {
            continue;
          }
          const auto planes = mesh::face_planes(mesh.mesh, static_cast<std::size_t>(mesh.original_of[t]));
          MarkerFace mf{static_cast<std::int32_t>(t), f, {}, {}, {}, {}};
          for (int c = 0; c < 3; ++c) mf.inward[c] = -planes[f].normal[c];
          const auto& l = mesh::kFaceLocalNodes[f];
          const V3 a = node(mesh, mf.tet, l[0]), b = node(mesh, mf.tet, l[1]), c = node(mesh, mf.tet, l[2]);
          std::copy(a.begin(), a.end(), mf.a);
          std::copy(b.begin(), b.end(), mf.b);
          std::copy(c.begin(), c.end(), mf.c);
          const V3 ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ac{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
          const V3 cr = cross(ab, ac);
          double area = 0.5 * std::sqrt(dot(cr, cr));
          if (source.marker_uses_direction) {
            const double cos_in = -dot(planes[f].normal, dir_);
            if (cos_in <= 0.0) continue;  // face turned away from the beam
            area *= cos_in;
          }
          total += area;
          marker_faces_.push_back(mf);
          marker_cdf_.push_back(total);
        }
      }
      if (marker_faces_.empty() || !(total > 0.0)) {
        throw SourceError(fmt::format("source outside the mesh: no boundary face carries marker {}{}",
                                      source.marker,
                                      source.marker_uses_direction ? " and faces the beam" : ""));
      }
      for (auto& c : marker_cdf_) c /= total;
      break;
    }
  }
}

Entry Launcher::sample(PhotonRng& rng) const {
  switch (source_.kind) {
    case Source::Kind::pencil:
      return pencil_;
    case Source::Kind::disk: {
      const double r = source_.radius_mm * std::sqrt(rng.uniform());
      const double phi = 2.0 * std::numbers::pi * rng.uniform();
      const double cu = r * std::cos(phi), cv = r * std::sin(phi);
      V3 o;
      for (int k = 0; k < 3; ++k) o[k] = source_.origin[k] + cu * e1_[k] + cv * e2_[k];
      return locator_.front().locate(o);
    }
    case Source::Kind::marker:
    default: {
      const double pick = rng.uniform();
      const auto idx = static_cast<std::size_t>(std::min<std::ptrdiff_t>(
          std::lower_bound(marker_cdf_.begin(), marker_cdf_.end(), pick) - marker_cdf_.begin(),
          static_cast<std::ptrdiff_t>(marker_cdf_.size()) - 1));
      const MarkerFace& f = marker_faces_[idx];
      // Uniform point in the triangle.
      const double s = std::sqrt(rng.uniform()), r2 = rng.uniform();
      const double wa = 1.0 - s, wb = s * (1.0 - r2), wc = s * r2;
      Entry e;
      e.tet = f.tet;
      e.face = f.face;
      for (int c = 0; c < 3; ++c) {
        e.pos[c] = wa * f.a[c] + wb * f.b[c] + wc * f.c[c];
        e.dir[c] = source_.marker_uses_direction ? dir_[c] : f.inward[c];
      }
      return e;
    }
  }
}

}  // namespace tocd::sim::mc

#include "tocd/sim/study/fluence_slices.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <fmt/format.h>

#include "tocd/core/atomic_file.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/mc/output.hpp"
#include "tocd/sim/mesh/topology.hpp"

namespace tocd::sim::study {
namespace {

int clamp_index(double v, int n) {
  return std::clamp(static_cast<int>(std::floor(v)), 0, n - 1);
}

}  // namespace

TetLocator::TetLocator(const mesh::TetMesh& mesh) : mesh_(&mesh) {
  const std::size_t count = mesh.tets.size();
  if (count == 0) {
    start_.assign(2, 0);
    return;
  }
  const mesh::BoundingBox box = mesh::bounding_box(mesh);
  double volume = 1.0;
  for (int k = 0; k < 3; ++k) volume *= std::max(box.max[k] - box.min[k], 1e-9);
  // About four tets per cell on average: cells a little larger than a tet.
  const double cell = std::cbrt(volume / static_cast<double>(count) * 4.0);
  for (int k = 0; k < 3; ++k) {
    lo_[k] = box.min[k];
    n_[k] = std::clamp(static_cast<int>(std::ceil((box.max[k] - box.min[k]) / cell)), 1, 1024);
    cell_[k] = std::max(box.max[k] - box.min[k], 1e-9) / n_[k];
  }
  const std::size_t buckets = static_cast<std::size_t>(n_[0]) * n_[1] * n_[2];
  auto range = [&](std::size_t t, int lo[3], int hi[3]) {
    mesh::Point3 a = mesh.nodes[mesh.tets[t][0]], b = a;
    for (int v = 1; v < 4; ++v)
      for (int k = 0; k < 3; ++k) {
        a[k] = std::min(a[k], mesh.nodes[mesh.tets[t][v]][k]);
        b[k] = std::max(b[k], mesh.nodes[mesh.tets[t][v]][k]);
      }
    for (int k = 0; k < 3; ++k) {
      lo[k] = clamp_index((a[k] - lo_[k]) / cell_[k], n_[k]);
      hi[k] = clamp_index((b[k] - lo_[k]) / cell_[k], n_[k]);
    }
  };
  auto bucket = [&](int i, int j, int k) { return (static_cast<std::size_t>(k) * n_[1] + j) * n_[0] + i; };
  std::vector<std::int32_t> counts(buckets + 1, 0);
  int lo[3], hi[3];
  for (std::size_t t = 0; t < count; ++t) {
    range(t, lo, hi);
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) ++counts[bucket(i, j, k) + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) counts[b + 1] += counts[b];
  start_ = counts;
  tets_.resize(static_cast<std::size_t>(counts[buckets]));
  for (std::size_t t = 0; t < count; ++t) {
    range(t, lo, hi);
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) tets_[counts[bucket(i, j, k)]++] = static_cast<std::int32_t>(t);
  }
}

bool TetLocator::contains(std::int32_t t, const mesh::Point3& p) const {
  const auto& tet = mesh_->tets[static_cast<std::size_t>(t)];
  const auto& n = mesh_->nodes;
  const double v = mesh::signed_volume(n[tet[0]], n[tet[1]], n[tet[2]], n[tet[3]]);
  if (v == 0.0) return false;
  // Barycentric coordinates as volume ratios; a relative tolerance keeps points on a shared
  // face or edge inside at least one tet despite round-off.
  const double tol = -1e-10 * std::abs(v);
  for (int f = 0; f < 4; ++f) {
    std::array<mesh::Point3, 4> q{n[tet[0]], n[tet[1]], n[tet[2]], n[tet[3]]};
    q[f] = p;
    const double part = mesh::signed_volume(q[0], q[1], q[2], q[3]);
    if ((v > 0 ? part : -part) < tol) return false;
  }
  return true;
}

std::int32_t TetLocator::find(const mesh::Point3& p) const {
  if (tets_.empty()) return -1;
  int idx[3];
  for (int k = 0; k < 3; ++k) {
    const double u = (p[k] - lo_[k]) / cell_[k];
    if (u < -1e-9 || u > n_[k] + 1e-9) return -1;
    idx[k] = clamp_index(u, n_[k]);
  }
  const std::size_t b = (static_cast<std::size_t>(idx[2]) * n_[1] + idx[1]) * n_[0] + idx[0];
  for (std::int32_t i = start_[b]; i < start_[b + 1]; ++i)
    if (contains(tets_[static_cast<std::size_t>(i)], p)) return tets_[static_cast<std::size_t>(i)];
  return -1;
}

std::vector<SliceSample> sample_slice(const mesh::TetMesh& mesh, const TetLocator& locator,
                                      const mc::Result& result, const SliceGrid& grid) {
  if (result.fluence_per_tet.size() != mesh.tets.size())
    throw tocd::Error("fluence slices need per-tet tallies from a run on this mesh (tally_per_tet on)");
  std::vector<SliceSample> out;
  out.reserve(static_cast<std::size_t>(grid.nu) * static_cast<std::size_t>(std::max(grid.nv, 0)));
  for (int j = 0; j < grid.nv; ++j)
    for (int i = 0; i < grid.nu; ++i) {
      SliceSample s;
      for (int k = 0; k < 3; ++k) s.p[k] = grid.origin[k] + i * grid.du[k] + j * grid.dv[k];
      s.tet = locator.find(s.p);
      if (s.tet >= 0) {
        const auto t = static_cast<std::size_t>(s.tet);
        s.region = mesh.regions[t];
        s.fluence = result.fluence_per_tet[t];
        s.fluence_se = result.fluence_per_tet_se[t];
      } else {
        s.fluence = s.fluence_se = std::numeric_limits<double>::quiet_NaN();
      }
      out.push_back(s);
    }
  return out;
}

void write_slice_csv(const std::vector<SliceSample>& samples, const std::filesystem::path& path) {
  tocd::AtomicFile file(path);
  std::ostream& out = file.stream();
  out << "x_mm,y_mm,z_mm,region,fluence,fluence_se\n";
  for (const auto& s : samples) {
    if (s.tet < 0)
      out << fmt::format("{:.6g},{:.6g},{:.6g},0,,\n", s.p[0], s.p[1], s.p[2]);
    else
      out << fmt::format("{:.6g},{:.6g},{:.6g},{},{:.9g},{:.9g}\n", s.p[0], s.p[1], s.p[2], s.region,
                         s.fluence, s.fluence_se);
  }
  file.commit();
}

std::vector<SliceGrid> standard_slices(const mesh::BoundingBox& box, double tip_z_mm, double spacing_mm) {
  if (!(spacing_mm > 0.0))
    throw tocd::ConfigError(fmt::format("slice spacing must be > 0 mm, got {}", spacing_mm));
  auto points = [&](double lo, double hi) {
    return static_cast<int>(std::floor((hi - lo) / spacing_mm + 1e-9)) + 1;
  };
  SliceGrid h{"horizontal",       {box.min[0], box.min[1], tip_z_mm}, {spacing_mm, 0, 0},
              {0, spacing_mm, 0}, points(box.min[0], box.max[0]),     points(box.min[1], box.max[1])};
  SliceGrid v{"vertical",         {box.min[0], 0.0, box.min[2]},  {spacing_mm, 0, 0},
              {0, 0, spacing_mm}, points(box.min[0], box.max[0]), points(box.min[2], box.max[2])};
  return {h, v};
}

FluenceFiles fluence_file_names(const std::filesystem::path& dir, const std::string& stem) {
  return {dir / (stem + ".vtu"), dir / (stem + "_horizontal.csv"), dir / (stem + "_vertical.csv")};
}

FluenceFiles write_fluence_files(const mc::PreparedMesh& mesh, const mc::Result& result, double tip_z_mm,
                                 const std::filesystem::path& dir, const std::string& stem, double spacing_mm,
                                 vtk::Format vtu_format) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw tocd::Error(fmt::format("cannot create fluence folder {}: {}", dir.string(), ec.message()));
  const FluenceFiles files = fluence_file_names(dir, stem);
  mc::write_fluence_vtu(mesh, result, files.vtu, vtu_format);
  const TetLocator locator(mesh.mesh);
  const auto grids = standard_slices(mesh.box, tip_z_mm, spacing_mm);
  write_slice_csv(sample_slice(mesh.mesh, locator, result, grids[0]), files.horizontal_csv);
  write_slice_csv(sample_slice(mesh.mesh, locator, result, grids[1]), files.vertical_csv);
  return files;
}

}  // namespace tocd::sim::study

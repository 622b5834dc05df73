#include "tocd/sim/mesh/slab_mesh.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "tocd/core/error.hpp"
#include "tocd/sim/mesh/topology.hpp"

namespace tocd::sim::mesh {
namespace {

// Tets = 6 per cell; the count is computed in floating point so that absurd cell counts are
// refused instead of overflowing.
double slab_tet_count(const SlabSpec& s) {
  double cells_z = 0.0;
  for (const auto& layer : s.layers) cells_z += layer.cells_z;
  return 6.0 * s.cells_x * s.cells_y * cells_z;
}

void check_length(double v, const char* what) {
  if (!(v > 0.0 && v <= kMaxSlabMm)) {
    throw tocd::ConfigError(
        fmt::format("slab {} {} mm is out of range: accepted above 0 up to {:g} mm", what, v, kMaxSlabMm));
  }
}

void check_spec(const SlabSpec& s) {
  check_length(s.width_mm, "width");
  check_length(s.depth_mm, "depth");
  if (s.cells_x < 1 || s.cells_y < 1) throw tocd::ConfigError("slab needs at least one cell in x and y");
  if (s.layers.empty()) throw tocd::ConfigError("slab needs at least one layer");
  for (std::size_t i = 0; i < s.layers.size(); ++i) {
    if (!(s.layers[i].thickness_mm > 0.0) || s.layers[i].cells_z < 1) {
      throw tocd::ConfigError(
          fmt::format("slab layer {} needs a positive thickness and at least one cell in z", i));
    }
    check_length(s.layers[i].thickness_mm, "layer thickness");
  }
  if (const double tets = slab_tet_count(s); tets > static_cast<double>(kMaxSlabTets)) {
    throw tocd::ConfigError(
        fmt::format("slab of {} x {} cells across would have {:.3g} tets; the limit is {} "
                    "(use fewer --slab-cells or a thinner slab)",
                    s.cells_x, s.cells_y, tets, kMaxSlabTets));
  }
}

void rotate(TetMesh& mesh, Point3 axis, double degrees, const Point3& centre) {
  const double len = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  if (!(len > 0.0)) throw tocd::ConfigError("slab rotation axis must be non-zero");
  for (auto& a : axis) a /= len;
  const double th = degrees * std::numbers::pi / 180.0, c = std::cos(th), s = std::sin(th);
  for (auto& p : mesh.nodes) {
    const Point3 v{p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]};
    const double kd = axis[0] * v[0] + axis[1] * v[1] + axis[2] * v[2];
    const Point3 kx{axis[1] * v[2] - axis[2] * v[1], axis[2] * v[0] - axis[0] * v[2],
                    axis[0] * v[1] - axis[1] * v[0]};
    // Rodrigues' formula.
    for (int k = 0; k < 3; ++k) p[k] = centre[k] + v[k] * c + kx[k] * s + axis[k] * kd * (1.0 - c);
  }
}

double parse_mm(const std::string& tok, const std::string& whole) {
  char* end = nullptr;
  const double v = std::strtod(tok.c_str(), &end);
  if (tok.empty() || *end != '\0' || !(v > 0.0)) {
    throw tocd::ConfigError(fmt::format("slab '{}': '{}' is not a positive length in mm", whole, tok));
  }
  if (!(v <= kMaxSlabMm)) {
    throw tocd::ConfigError(fmt::format("slab '{}': {} mm is out of range: accepted above 0 up to {:g} mm",
                                        whole, tok, kMaxSlabMm));
  }
  return v;
}

}  // namespace

SlabSpec parse_slab_spec(const std::string& text, int cells_across) {
  if (cells_across < 1 || cells_across > kMaxSlabCellsAcross) {
    throw tocd::ConfigError(fmt::format("slab cells across {} is out of range: accepted 1 to {}",
                                        cells_across, kMaxSlabCellsAcross));
  }
  SlabSpec spec;
  spec.cells_x = spec.cells_y = cells_across;
  const auto colon = text.find(':');
  const std::string size = text.substr(0, colon);
  std::vector<std::string> dims;
  for (std::size_t pos = 0;;) {
    const auto x = size.find('x', pos);
    dims.push_back(size.substr(pos, x - pos));
    if (x == std::string::npos) break;
    pos = x + 1;
  }
  const std::size_t want = colon == std::string::npos ? 3 : 2;
  if (dims.size() != want) {
    throw tocd::ConfigError(fmt::format("slab '{}': expected WxDxT or WxD:T1@R1,T2@R2,... (mm)", text));
  }
  spec.width_mm = parse_mm(dims[0], text);
  spec.depth_mm = parse_mm(dims[1], text);
  spec.layers.clear();
  const double cell_mm = std::min(spec.width_mm, spec.depth_mm) / cells_across;
  auto layer = [&](double thickness, std::int32_t region) {
    // Clamped before the cast: a thin, wide slab asks for absurd z counts, which check_spec
    // then refuses by the tet limit rather than by an overflowed int.
    const double cz =
        std::clamp(std::ceil(thickness / cell_mm - 1e-9), 2.0, static_cast<double>(kMaxSlabTets));
    spec.layers.push_back({thickness, region, static_cast<int>(cz)});
  };
  if (colon == std::string::npos) {
    layer(parse_mm(dims[2], text), 1);
    return spec;
  }
  const std::string rest = text.substr(colon + 1);
  for (std::size_t pos = 0; pos <= rest.size();) {
    const auto comma = std::min(rest.find(',', pos), rest.size());
    const std::string item = rest.substr(pos, comma - pos);
    const auto at = item.find('@');
    if (at == std::string::npos) {
      throw tocd::ConfigError(fmt::format("slab '{}': layer '{}' must be THICKNESS@REGION", text, item));
    }
    char* end = nullptr;
    const std::string region_text = item.substr(at + 1);
    errno = 0;
    const long long region = std::strtoll(region_text.c_str(), &end, 10);
    if (region_text.empty() || *end != '\0' || errno == ERANGE || region < INT32_MIN || region > INT32_MAX) {
      throw tocd::ConfigError(fmt::format("slab '{}': region '{}' is not an integer in [{}, {}]", text,
                                          region_text, INT32_MIN, INT32_MAX));
    }
    layer(parse_mm(item.substr(0, at), text), static_cast<std::int32_t>(region));
    pos = comma + 1;
  }
  return spec;
}

TetMesh make_slab(const SlabSpec& spec) {
  check_spec(spec);
  // z levels from the bottom up; layers are listed top-down.
  std::vector<double> z{0.0};
  std::vector<std::int32_t> cell_region;  // per z cell, bottom-up
  for (auto it = spec.layers.rbegin(); it != spec.layers.rend(); ++it) {
    const double z0 = z.back();
    for (int k = 1; k <= it->cells_z; ++k) {
      z.push_back(z0 + it->thickness_mm * k / it->cells_z);
      cell_region.push_back(it->region);
    }
  }
  const int nx = spec.cells_x, ny = spec.cells_y, nz = static_cast<int>(cell_region.size());
  TetMesh mesh;
  mesh.nodes.reserve(static_cast<std::size_t>(nx + 1) * (ny + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        mesh.nodes.push_back({-0.5 * spec.width_mm + spec.width_mm * i / nx,
                              -0.5 * spec.depth_mm + spec.depth_mm * j / ny, z[static_cast<std::size_t>(k)]});
  auto node = [&](int i, int j, int k) {
    return static_cast<std::int32_t>((k * (ny + 1) + j) * (nx + 1) + i);
  };

  // Kuhn triangulation: the 6 monotone paths from corner 0 to corner 7 of each cell. Every
  // cell uses the same diagonal direction, which makes neighbouring cells share faces.
  static constexpr int kAxisOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  mesh.tets.reserve(static_cast<std::size_t>(nx) * ny * nz * 6);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& order : kAxisOrders) {
          std::array<int, 3> c{i, j, k};
          std::array<std::int32_t, 4> tet{};
          tet[0] = node(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[order[s]];
            tet[s + 1] = node(c[0], c[1], c[2]);
          }
          if (signed_volume(mesh.nodes[tet[0]], mesh.nodes[tet[1]], mesh.nodes[tet[2]], mesh.nodes[tet[3]]) <
              0.0) {
            std::swap(tet[2], tet[3]);
          }
          mesh.tets.push_back(tet);
          mesh.regions.push_back(cell_region[static_cast<std::size_t>(k)]);
        }

  // Boundary faces with markers, classified by their outward normal before any rotation.
  const FaceAdjacency adj = build_face_adjacency(mesh);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto planes = face_planes(mesh, t);
    for (int f = 0; f < 4; ++f) {
      if (adj.neighbour[t][f] >= 0) continue;
      const auto& l = kFaceLocalNodes[f];
      const double nz_out = planes[f].normal[2];
      const std::int32_t marker =
          nz_out > 0.5 ? kSlabTopMarker : (nz_out < -0.5 ? kSlabBottomMarker : kSlabSideMarker);
      mesh.boundary_faces.push_back({{mesh.tets[t][l[0]], mesh.tets[t][l[1]], mesh.tets[t][l[2]]}, marker});
    }
  }
  if (spec.rotation_deg != 0.0)
    rotate(mesh, spec.rotation_axis, spec.rotation_deg, {0.0, 0.0, 0.5 * z.back()});
  return mesh;
}

}  // namespace tocd::sim::mesh

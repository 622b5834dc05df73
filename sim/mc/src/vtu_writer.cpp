#include "tocd/core/error.hpp"
#include "tocd/sim/mc/output.hpp"

namespace tocd::sim::mc {

void write_fluence_vtu(const PreparedMesh& mesh, const Result& result, const std::filesystem::path& path,
                       vtk::Format format) {
  const auto& m = mesh.mesh;
  if (result.fluence_per_tet.size() != m.tets.size()) {
    throw tocd::Error("fluence output needs per-tet tallies from a run on this mesh (tally_per_tet on)");
  }
  vtk::UnstructuredGrid g;
  g.points_xyz.reserve(3 * m.nodes.size());
  for (const auto& p : m.nodes) g.points_xyz.insert(g.points_xyz.end(), {p[0], p[1], p[2]});
  g.connectivity.reserve(4 * m.tets.size());
  for (const auto& t : m.tets) g.connectivity.insert(g.connectivity.end(), {t[0], t[1], t[2], t[3]});
  g.nodes_per_cell = 4;
  g.cell_type = 10;  // VTK_TETRA
  // Tallies with standard errors of a percent or more: Float32's 7 digits lose nothing, and
  // halve what zlib cannot shrink (noise).
  g.single_precision = true;
  g.cell_data.push_back({"fluence", 1, result.fluence_per_tet});
  g.cell_data.push_back({"fluence_se", 1, result.fluence_per_tet_se});
  g.cell_data.push_back({"absorbed", 1, result.absorbed_per_tet});
  g.cell_data.push_back({"region", 1, std::vector<std::int32_t>(m.regions.begin(), m.regions.end())});
  vtk::write_vtu(g, path, format);
}

}  // namespace tocd::sim::mc

#include <fmt/format.h>

#include "tocd/core/atomic_file.hpp"
#include "tocd/sim/mc/output.hpp"

namespace tocd::sim::mc {

void write_fluence_vtu(const PreparedMesh& mesh, const Result& result, const std::filesystem::path& path) {
  const auto& m = mesh.mesh;
  if (result.fluence_per_tet.size() != m.tets.size()) {
    throw tocd::Error("fluence output needs per-tet tallies from a run on this mesh (tally_per_tet on)");
  }
  tocd::AtomicFile file(path);  // a killed run leaves no .vtu that looks complete
  std::ostream& out = file.stream();
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n"
         "<UnstructuredGrid>\n";
  out << fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", m.nodes.size(), m.tets.size());
  out << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : m.nodes) out << fmt::format("{:.9g} {:.9g} {:.9g}\n", p[0], p[1], p[2]);
  out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" "
         "format=\"ascii\">\n";
  for (const auto& t : m.tets) out << fmt::format("{} {} {} {}\n", t[0], t[1], t[2], t[3]);
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 1; i <= m.tets.size(); ++i) out << 4 * i << (i % 16 == 0 ? '\n' : ' ');
  out << "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 1; i <= m.tets.size(); ++i) out << "10" << (i % 32 == 0 ? '\n' : ' ');  // VTK_TETRA
  out << "\n</DataArray>\n</Cells>\n<CellData Scalars=\"fluence\">\n";
  out << "<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < m.regions.size(); ++i) out << m.regions[i] << ((i + 1) % 16 == 0 ? '\n' : ' ');
  out << "\n</DataArray>\n";
  auto doubles = [&](const char* name, const std::vector<double>& v) {
    out << fmt::format("<DataArray type=\"Float64\" Name=\"{}\" format=\"ascii\">\n", name);
    for (std::size_t i = 0; i < v.size(); ++i)
      out << fmt::format("{:.9g}{}", v[i], (i + 1) % 8 == 0 ? '\n' : ' ');
    out << "\n</DataArray>\n";
  };
  doubles("fluence", result.fluence_per_tet);
  doubles("fluence_se", result.fluence_per_tet_se);
  doubles("absorbed", result.absorbed_per_tet);
  out << "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  file.commit();
}

}  // namespace tocd::sim::mc

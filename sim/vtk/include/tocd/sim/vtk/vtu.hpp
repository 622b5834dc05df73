#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace tocd::sim::vtk {

/// How a .vtu stores its arrays. `binary` (the default everywhere): one appended raw block,
/// each array zlib-compressed (vtkZLibDataCompressor, UInt64 headers), several times smaller
/// and faster to load than `ascii`, which is plain text for reading by eye or by scripts.
enum class Format { binary, ascii };

/// "binary" | "ascii"; anything else throws tocd::ConfigError naming the value.
Format parse_format(std::string_view name);
const char* to_string(Format format);

/// One named array of point or cell data. ASCII writes Float64 with 9 significant digits;
/// binary keeps every bit.
struct DataArray {
  std::string name;
  int components = 1;
  std::variant<std::vector<double>, std::vector<std::int64_t>, std::vector<std::int32_t>,
               std::vector<std::uint8_t>>
      values;
};

/// A VTK XML UnstructuredGrid of one cell type. Points are xyz triples.
struct UnstructuredGrid {
  std::vector<double> points_xyz;          ///< 3 per point
  std::vector<std::int64_t> connectivity;  ///< `nodes_per_cell` per cell
  int nodes_per_cell = 4;
  std::uint8_t cell_type = 10;                   ///< VTK cell type (10 tetra, 9 quad)
  std::vector<DataArray> point_data, cell_data;  ///< the first of each is the active one
  std::string active_point_vectors;              ///< name of the point array shown as vectors
};

/// Writes `grid` to `path` atomically (tocd::AtomicFile): a killed run leaves no .vtu that
/// looks complete. Throws tocd::Error when the file cannot be written or an array's size
/// does not match the points or cells.
void write_vtu(const UnstructuredGrid& grid, const std::filesystem::path& path,
               Format format = Format::binary);

}  // namespace tocd::sim::vtk

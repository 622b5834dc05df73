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

/// One named array of point or cell data, stored with its own type. Binary keeps every bit.
/// ASCII writes Float64 with 9 significant digits and Float32 with 9 too, which restores each
/// float exactly (std::numeric_limits<float>::max_digits10): for a Float32 array both formats
/// hold the same values. Float32 suits quantities known to far fewer digits than 7 (Monte
/// Carlo tallies) and halves their size.
struct DataArray {
  std::string name;
  int components = 1;
  std::variant<std::vector<double>, std::vector<float>, std::vector<std::int64_t>, std::vector<std::int32_t>,
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
  /// Write the points and every Float64 array as Float32, in both formats (the ASCII's 9
  /// digits then restore each float exactly, so both files hold the same values). For fields
  /// known to far fewer than 7 digits, such as Monte Carlo tallies with their standard
  /// errors; it halves their bytes, which zlib cannot do for noise.
  bool single_precision = false;
};

/// Writes `grid` to `path` atomically (tocd::AtomicFile): a killed run leaves no .vtu that
/// looks complete. Cells are written ordered by their two lowest point indices (each cell's
/// own point order, hence its orientation, kept; cell data follows its cell): neighbouring
/// cells then share points, which halves the compressed connectivity of a TetGen mesh. Throws tocd::Error
/// when the file cannot be written or an array's size does not match the points or cells.
void write_vtu(const UnstructuredGrid& grid, const std::filesystem::path& path,
               Format format = Format::binary);

}  // namespace tocd::sim::vtk

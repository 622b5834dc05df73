#include "tocd/sim/mesh/tetgen_io.hpp"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "tocd/sim/mesh/mesh_error.hpp"

namespace tocd::sim::mesh {
namespace {

// TetGen files carry a handful of element attributes; more is a corrupt header.
constexpr int kMaxAttributes = 64;

// Reads a TetGen file as rows of numbers, skipping blank lines and '#' comments, and keeps
// the line number of each row for error messages.
class TableReader {
 public:
  explicit TableReader(const std::filesystem::path& path) : path_(path), in_(path) {
    if (!in_) throw MeshError(fmt::format("cannot open {}", path.string()));
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) throw MeshError(fmt::format("cannot open {}: not a regular file", path.string()));
    file_bytes_ = size;
  }

  // Next non-empty row as numbers; false at end of file.
  bool next(std::vector<double>& row) {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_no_;
      if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
      std::istringstream ss(line);
      row.clear();
      std::string tok;
      while (ss >> tok) {
        char* end = nullptr;
        const double v = std::strtod(tok.c_str(), &end);
        if (end == tok.c_str() || *end != '\0') fail(fmt::format("'{}' is not a number", tok));
        row.push_back(v);
      }
      if (!row.empty()) return true;
    }
    return false;
  }

  std::vector<double> require(std::size_t min_columns, const char* what) {
    std::vector<double> row;
    if (!next(row)) fail(fmt::format("file ends before {}", what));
    if (row.size() < min_columns)
      fail(fmt::format("{} needs at least {} numbers, found {}", what, min_columns, row.size()));
    return row;
  }

  [[noreturn]] void fail(const std::string& why) const {
    throw MeshError(fmt::format("{}:{}: {}", path_.string(), line_no_, why));
  }

  // A header count: a whole number no larger than the file can hold (each row is at least
  // `min_row_bytes` long) nor than kMaxMeshItems, checked before anything is allocated.
  std::int64_t as_count(double v, std::size_t min_row_bytes, const char* what) const {
    const std::int64_t fits = static_cast<std::int64_t>(file_bytes_ / min_row_bytes);
    const std::int64_t limit = std::min<std::int64_t>(kMaxMeshItems, fits);
    if (!(v >= 0.0) || v != std::floor(v) || v > static_cast<double>(limit)) {
      fail(
          fmt::format("{} {} is out of range: accepted 0 to {} (at most {} items, and a {}-byte file "
                      "holds at most {} rows)",
                      what, v, limit, kMaxMeshItems, file_bytes_, fits));
    }
    return static_cast<std::int64_t>(v);
  }

  // A small non-negative integer from a header (attribute count, marker flag).
  int as_small(double v, int max, const char* what) const {
    if (!(v >= 0.0) || v != std::floor(v) || v > max)
      fail(fmt::format("{} {} is out of range: accepted 0 to {}", what, v, max));
    return static_cast<int>(v);
  }

  // A region id or boundary marker: any whole number an int32 holds.
  std::int32_t as_label(double v, const char* what) const {
    constexpr double lo = std::numeric_limits<std::int32_t>::min();
    constexpr double hi = std::numeric_limits<std::int32_t>::max();
    if (v != std::floor(v) || !(v >= lo && v <= hi))
      fail(fmt::format("{} {} is not an integer in [{}, {}]", what, v, lo, hi));
    return static_cast<std::int32_t>(v);
  }

  // A node coordinate in mm: finite and within kMaxCoordinateMm of the origin.
  double as_coordinate(double v, char axis) const {
    if (!(std::abs(v) <= kMaxCoordinateMm))
      fail(fmt::format("node coordinate {} = {} is out of range: accepted -{:g} to {:g} mm", axis, v,
                       kMaxCoordinateMm, kMaxCoordinateMm));
    return v;
  }

  /// Fails when index `i` (0-based) was given before: each row numbers its own item, and a
  /// repeated number would leave another item unset (read as node 0 four times: "degenerate").
  void first_time(std::vector<bool>& seen, std::int32_t i, const char* what, std::int64_t base) const {
    if (seen[static_cast<std::size_t>(i)]) fail(fmt::format("{} {} is given twice", what, i + base));
    seen[static_cast<std::size_t>(i)] = true;
  }

  std::int32_t as_index(double v, std::int64_t base, std::int64_t count, const char* what) const {
    if (v != std::floor(v)) fail(fmt::format("{} {} is not an integer", what, v));
    if (!(v >= static_cast<double>(base) && v < static_cast<double>(base + count)))
      fail(fmt::format("{} {} is out of range ({} items, first index {})", what, v, count, base));
    const auto i = static_cast<std::int64_t>(v) - base;
    if (i < 0 || i >= count)
      fail(fmt::format("{} {} is out of range ({} items, first index {})", what, v, count, base));
    return static_cast<std::int32_t>(i);
  }

 private:
  std::filesystem::path path_;
  std::ifstream in_;
  std::uintmax_t file_bytes_ = 0;
  int line_no_ = 0;
};

std::filesystem::path with_ext(const std::filesystem::path& prefix, const char* ext) {
  return std::filesystem::path(prefix.string() + ext);
}

}  // namespace

TetMesh read_tetgen(const std::filesystem::path& prefix) {
  TetMesh mesh;
  std::int64_t base = 0;
  {
    TableReader r(with_ext(prefix, ".node"));
    const auto head = r.require(1, "the .node header");
    // Shortest node row: "0 0 0 0\n".
    const auto count = r.as_count(head[0], 8, "node count");
    if (head.size() > 1 && head[1] != 3)
      r.fail(fmt::format("dimension {} given, only 3 is supported", head[1]));
    mesh.nodes.resize(static_cast<std::size_t>(count));
    std::vector<bool> seen(static_cast<std::size_t>(count), false);
    for (std::int64_t i = 0; i < count; ++i) {
      const auto row = r.require(4, "a node row (index x y z)");
      // Compared as a double before any conversion: a first index of 1e37 must be an error,
      // not an out-of-range cast (found by the tetgen_mesh fuzz target).
      if (i == 0 && row[0] != 0 && row[0] != 1) r.fail("node indices must start at 0 or 1");
      if (i == 0) base = row[0] == 1 ? 1 : 0;
      const auto idx = r.as_index(row[0], base, count, "node index");
      r.first_time(seen, idx, "node index", base);
      mesh.nodes[static_cast<std::size_t>(idx)] = {r.as_coordinate(row[1], 'x'), r.as_coordinate(row[2], 'y'),
                                                   r.as_coordinate(row[3], 'z')};
    }
  }
  const auto nn = static_cast<std::int64_t>(mesh.nodes.size());
  {
    TableReader r(with_ext(prefix, ".ele"));
    const auto head = r.require(2, "the .ele header (count nodes-per-tet [attributes])");
    // Shortest tet row: "0 0 0 0 0\n".
    const auto count = r.as_count(head[0], 10, "tet count");
    if (head[1] != 4 && head[1] != 10) r.fail(fmt::format("{} nodes per tet; expected 4 or 10", head[1]));
    const int per_tet = static_cast<int>(head[1]);
    const int attrs = head.size() > 2 ? r.as_small(head[2], kMaxAttributes, "attribute count") : 0;
    mesh.tets.resize(static_cast<std::size_t>(count));
    mesh.regions.assign(static_cast<std::size_t>(count), 0);
    std::vector<bool> seen(static_cast<std::size_t>(count), false);
    for (std::int64_t i = 0; i < count; ++i) {
      const auto row = r.require(static_cast<std::size_t>(1 + per_tet + attrs), "a tet row");
      const auto t = static_cast<std::size_t>(r.as_index(row[0], base, count, "tet index"));
      r.first_time(seen, static_cast<std::int32_t>(t), "tet index", base);
      for (int k = 0; k < 4; ++k) mesh.tets[t][k] = r.as_index(row[1 + k], base, nn, "node");
      if (attrs > 0) {
        mesh.regions[t] = r.as_label(row[1 + per_tet], "region attribute");
      }
    }
  }
  if (std::filesystem::exists(with_ext(prefix, ".face"))) {
    TableReader r(with_ext(prefix, ".face"));
    const auto head = r.require(1, "the .face header (count [markers])");
    // Shortest face row: "0 0 0 0\n".
    const auto count = r.as_count(head[0], 8, "face count");
    const bool markers = head.size() > 1 && r.as_small(head[1], 1, "boundary marker flag") != 0;
    mesh.boundary_faces.resize(static_cast<std::size_t>(count));
    for (std::int64_t i = 0; i < count; ++i) {
      const auto row = r.require(markers ? 5 : 4, "a face row (index a b c [marker])");
      auto& face = mesh.boundary_faces[static_cast<std::size_t>(i)];
      for (int k = 0; k < 3; ++k) face.nodes[k] = r.as_index(row[1 + k], base, nn, "node");
      face.marker = markers ? r.as_label(row[4], "boundary marker") : 0;
    }
  }
  return mesh;
}

void write_tetgen(const TetMesh& mesh, const std::filesystem::path& prefix) {
  auto open = [&](const char* ext) {
    std::ofstream out(with_ext(prefix, ext));
    if (!out) throw MeshError(fmt::format("cannot write {}", with_ext(prefix, ext).string()));
    return out;
  };
  {
    auto out = open(".node");
    out << mesh.nodes.size() << " 3 0 0\n";
    for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
      const auto& p = mesh.nodes[i];
      out << fmt::format("{} {:.17g} {:.17g} {:.17g}\n", i, p[0], p[1], p[2]);
    }
  }
  {
    auto out = open(".ele");
    out << mesh.tets.size() << " 4 1\n";
    for (std::size_t i = 0; i < mesh.tets.size(); ++i) {
      const auto& t = mesh.tets[i];
      out << fmt::format("{} {} {} {} {} {}\n", i, t[0], t[1], t[2], t[3], mesh.regions[i]);
    }
  }
  auto out = open(".face");
  out << mesh.boundary_faces.size() << " 1\n";
  for (std::size_t i = 0; i < mesh.boundary_faces.size(); ++i) {
    const auto& f = mesh.boundary_faces[i];
    out << fmt::format("{} {} {} {} {}\n", i, f.nodes[0], f.nodes[1], f.nodes[2], f.marker);
  }
  if (!out) throw MeshError(fmt::format("error writing {}", with_ext(prefix, ".face").string()));
}

}  // namespace tocd::sim::mesh

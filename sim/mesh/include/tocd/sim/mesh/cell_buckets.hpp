#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tocd::sim::mesh {

/// Items sorted into the cells of a uniform grid, as compressed rows: the items of cell c are
/// items[start[c]] to items[start[c + 1] - 1], in ascending order. The grids that locate points
/// in a mesh (tets by bounding box, boundary faces by projection) are built this way.
struct CellBuckets {
  std::vector<std::size_t> start;
  std::vector<std::int32_t> items;
};

/// Buckets `item_count` items over `cell_count` cells in two passes (count, then fill):
/// `cells_of(k, add)` calls add(c) for every cell c that item k overlaps.
template <class CellsOf>
CellBuckets bucket_by_cell(std::size_t item_count, std::size_t cell_count, CellsOf cells_of) {
  CellBuckets b;
  b.start.assign(cell_count + 1, 0);
  for (std::size_t k = 0; k < item_count; ++k) cells_of(k, [&](std::size_t c) { ++b.start[c + 1]; });
  for (std::size_t c = 1; c < b.start.size(); ++c) b.start[c] += b.start[c - 1];
  b.items.resize(b.start.back());
  std::vector<std::size_t> fill(b.start.begin(), b.start.end() - 1);
  for (std::size_t k = 0; k < item_count; ++k)
    cells_of(k, [&](std::size_t c) { b.items[fill[c]++] = static_cast<std::int32_t>(k); });
  return b;
}

}  // namespace tocd::sim::mesh

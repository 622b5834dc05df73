#include <cmath>
#include <map>
#include <utility>

#include "step_output.hpp"

namespace tocd::sim::fe {

std::vector<std::vector<int>> region_loops(const FeMesh& m, const std::vector<char>& flagged) {
  const int ner = m.nodes_r - 1, nez = m.nodes_z - 1;
  auto is_flagged = [&](int i, int j) {
    return i >= 0 && j >= 0 && i < ner && j < nez && flagged[j * ner + i];
  };
  struct HalfEdge {
    int from, to;
    bool used = false;
  };
  std::vector<HalfEdge> edges;
  std::multimap<int, int> outgoing;  // node -> half-edge index
  for (int j = 0; j < nez; ++j)
    for (int i = 0; i < ner; ++i) {
      if (!is_flagged(i, j)) continue;
      const auto& q = m.quads[j * ner + i];
      // Edges of a CCW quad: bottom, right, top, left; neighbour across each.
      const int ni[4] = {i, i + 1, i, i - 1}, nj[4] = {j - 1, j, j + 1, j};
      for (int k = 0; k < 4; ++k) {
        if (is_flagged(ni[k], nj[k])) continue;
        outgoing.emplace(q[k], static_cast<int>(edges.size()));
        edges.push_back({q[k], q[(k + 1) % 4]});
      }
    }
  auto dir = [&](const HalfEdge& e) {
    return std::pair<double, double>(m.nodes[e.to].r_mm - m.nodes[e.from].r_mm,
                                     m.nodes[e.to].z_mm - m.nodes[e.from].z_mm);
  };
  std::vector<std::vector<int>> loops;
  for (std::size_t start = 0; start < edges.size(); ++start) {
    if (edges[start].used) continue;
    std::vector<int> loop;
    int cur = static_cast<int>(start);
    while (!edges[cur].used) {
      edges[cur].used = true;
      loop.push_back(edges[cur].from);
      // Leftmost turn among the unused half-edges leaving the end vertex.
      const auto [dx, dz] = dir(edges[cur]);
      int best = -1;
      double best_angle = -10;
      auto range = outgoing.equal_range(edges[cur].to);
      for (auto it = range.first; it != range.second; ++it) {
        if (edges[it->second].used && it->second != static_cast<int>(start)) continue;
        const auto [ex, ez] = dir(edges[it->second]);
        const double ang = std::atan2(dx * ez - dz * ex, dx * ex + dz * ez);
        if (ang > best_angle) {
          best_angle = ang;
          best = it->second;
        }
      }
      if (best < 0 || best == static_cast<int>(start)) break;
      cur = best;
    }
    // Every grid vertex is kept: straight in the reference layout, the outline bends with the
    // deformation.
    if (loop.size() >= 3) loops.push_back(std::move(loop));
  }
  return loops;
}

}  // namespace tocd::sim::fe

#include "tetgen_mesher.hpp"

#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <sys/wait.h>
#include <tetgen.h>
#include <unistd.h>

#include "tocd/sim/geometry/composite.hpp"

namespace tocd::sim::geometry::detail {

namespace {

void fill_input(const Plc& plc, tetgenio& in) {
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(plc.points.size());
  in.pointlist = new REAL[plc.points.size() * 3];
  for (std::size_t i = 0; i < plc.points.size(); ++i)
    for (int k = 0; k < 3; ++k) in.pointlist[3 * i + k] = plc.points[i][k];
  in.numberoffacets = static_cast<int>(plc.facets.size());
  in.facetlist = new tetgenio::facet[plc.facets.size()];
  in.facetmarkerlist = new int[plc.facets.size()];
  for (std::size_t f = 0; f < plc.facets.size(); ++f) {
    const Facet& src = plc.facets[f];
    tetgenio::facet& dst = in.facetlist[f];
    tetgenio::init(&dst);
    dst.numberofpolygons = static_cast<int>(src.polygons.size());
    dst.polygonlist = new tetgenio::polygon[src.polygons.size()];
    for (std::size_t p = 0; p < src.polygons.size(); ++p) {
      tetgenio::polygon& poly = dst.polygonlist[p];
      tetgenio::init(&poly);
      poly.numberofvertices = static_cast<int>(src.polygons[p].vertices.size());
      poly.vertexlist = new int[src.polygons[p].vertices.size()];
      for (std::size_t v = 0; v < src.polygons[p].vertices.size(); ++v)
        poly.vertexlist[v] = src.polygons[p].vertices[v];
    }
    if (!src.holes.empty()) {
      dst.numberofholes = static_cast<int>(src.holes.size());
      dst.holelist = new REAL[src.holes.size() * 3];
      for (std::size_t h = 0; h < src.holes.size(); ++h)
        for (int k = 0; k < 3; ++k) dst.holelist[3 * h + k] = src.holes[h][k];
    }
    in.facetmarkerlist[f] = src.surface + 1;
  }
  in.numberofregions = static_cast<int>(plc.seeds.size());
  in.regionlist = new REAL[plc.seeds.size() * 5];
  for (std::size_t r = 0; r < plc.seeds.size(); ++r) {
    for (int k = 0; k < 3; ++k) in.regionlist[5 * r + k] = plc.seeds[r].point[k];
    in.regionlist[5 * r + 3] = plc.seeds[r].region;
    in.regionlist[5 * r + 4] = 0;
  }
}

std::string code_meaning(int code) {
  switch (code) {
    case 1:
      return "out of memory";
    case 2:
      return "internal error";
    case 3:
      return "the surfaces intersect each other";
    case 4:
      return "an input feature is too small for its tolerance";
    case 5:
      return "two input facets are too close to each other";
    case 10:
      return "invalid input";
    default:
      return fmt::format("error code {}", code);
  }
}

/// Runs `switches` on the complex in a child process and returns its TetGen error code (0:
/// accepted; -1: the child crashed). Debian's libtet 1.5 frees its pools twice on its error
/// path and crashes instead of throwing, so a complex is probed in isolation before it is
/// meshed. With fd >= 0 the child writes the facet markers of TetGen's output faces to it.
int probe(const Plc& plc, const char* switches, int fd) {
  const pid_t pid = fork();
  if (pid < 0) return 0;  // cannot probe: mesh directly
  if (pid == 0) {
    int code = 0;
    try {
      tetgenio in, out;
      fill_input(plc, in);
      std::string text(switches);
      std::vector<char> sw(text.begin(), text.end());
      sw.push_back('\0');
      ::tetrahedralize(sw.data(), &in, &out);
      if (fd >= 0 && out.trifacemarkerlist) {
        for (int f = 0; f < out.numberoftrifaces; ++f) {
          const int m = out.trifacemarkerlist[f];
          if (write(fd, &m, sizeof m) != static_cast<ssize_t>(sizeof m)) break;
        }
      }
    } catch (int c) {
      code = c;
    } catch (...) {
      code = 2;
    }
    _exit(code);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return 0;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return -1;
}

/// Reruns TetGen's intersection detection (in a child) and names the surfaces it reports.
std::string surfaces_at_fault(const Plc& plc, const Section& section) {
  int fds[2];
  if (pipe(fds) != 0) return {};
  probe(plc, "pdzQ", fds[1]);
  close(fds[1]);
  std::set<int> surfaces;
  int m = 0;
  while (read(fds[0], &m, sizeof m) == static_cast<ssize_t>(sizeof m)) surfaces.insert(m - 1);
  close(fds[0]);
  std::string names;
  for (int s : surfaces) {
    if (s < 0 || s >= static_cast<int>(section.surfaces.size())) continue;
    names += (names.empty() ? "" : ", ") + section.surfaces[static_cast<std::size_t>(s)].name;
  }
  return names;
}

[[noreturn]] void reject(int code, const Plc& plc, const Section& section) {
  const std::string names = surfaces_at_fault(plc, section);
  const std::string reason =
      code < 0 ? "TetGen failed while recovering the surfaces (self-intersecting or nearly touching facets)"
               : code_meaning(code);
  throw GeometryError(
      fmt::format("TetGen rejected the composite geometry: {}{}", reason,
                  names.empty() ? std::string{} : fmt::format(" (surfaces involved: {})", names)));
}

}  // namespace

tocd::sim::mesh::TetMesh tetrahedralize(const Plc& plc, const Section& section, const std::string& switches) {
  tetgenio in, out;
  fill_input(plc, in);
  // z: 0-based output; A: region attributes from the seeds.
  std::string sw = switches + "zA";
  std::vector<char> buffer(sw.begin(), sw.end());
  buffer.push_back('\0');
  // Surface recovery is where a bad complex fails; it is cheap next to the refinement.
  if (const int code = probe(plc, "pzQ", -1); code != 0) reject(code, plc, section);
  try {
    ::tetrahedralize(buffer.data(), &in, &out);
  } catch (int code) {
    reject(code, plc, section);
  }
  tocd::sim::mesh::TetMesh mesh;
  mesh.nodes.resize(static_cast<std::size_t>(out.numberofpoints));
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i)
    mesh.nodes[i] = {out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]};
  const auto nt = static_cast<std::size_t>(out.numberoftetrahedra);
  mesh.tets.resize(nt);
  mesh.regions.resize(nt);
  const int stride = out.numberofcorners;
  const int attributes = out.numberoftetrahedronattributes;
  for (std::size_t t = 0; t < nt; ++t) {
    auto& tet = mesh.tets[t];
    for (int k = 0; k < 4; ++k) tet[k] = out.tetrahedronlist[stride * t + static_cast<std::size_t>(k)];
    if (tocd::sim::mesh::signed_volume(mesh.nodes[tet[0]], mesh.nodes[tet[1]], mesh.nodes[tet[2]],
                                       mesh.nodes[tet[3]]) < 0)
      std::swap(tet[2], tet[3]);
    mesh.regions[t] =
        attributes > 0 ? static_cast<std::int32_t>(out.tetrahedronattributelist[attributes * t]) : 0;
    if (mesh.regions[t] < pin || mesh.regions[t] > compressed)
      throw GeometryError(
          fmt::format("TetGen left tet {} outside every region (attribute {}): a surface of the "
                      "composite is not closed",
                      t, mesh.regions[t]));
  }
  for (int f = 0; f < out.numberoftrifaces; ++f) {
    const int surface = out.trifacemarkerlist ? out.trifacemarkerlist[f] - 1 : -1;
    if (surface < 0 || surface >= static_cast<int>(section.surfaces.size())) continue;
    const int marker = section.surfaces[static_cast<std::size_t>(surface)].boundary_marker;
    if (marker <= 0) continue;
    mesh.boundary_faces.push_back(
        {{out.trifacelist[3 * f], out.trifacelist[3 * f + 1], out.trifacelist[3 * f + 2]}, marker});
  }
  return mesh;
}

}  // namespace tocd::sim::geometry::detail

#include "tetgen_mesher.hpp"

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <optional>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <sys/wait.h>
#include <tetgen.h>
#include <unistd.h>

#include "tocd/core/error.hpp"
#include "tocd/sim/geometry/composite.hpp"

namespace tocd::sim::geometry::detail {

namespace {

/// TetGen's facet marker of a section surface, and back: markers start at 1, since TetGen
/// gives 0 to faces of no facet.
constexpr int marker_of(int surface) {
  return surface + 1;
}
constexpr int surface_of(int marker) {
  return marker - 1;
}

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
    in.facetmarkerlist[f] = marker_of(src.surface);
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

/// TetGen's output as the meshing child sends it: counts, then the arrays, in this order.
struct MeshOutput {
  std::vector<double> points;     // x y z per node
  std::vector<int> tets;          // 4 nodes per tet
  std::vector<double> region;     // the tet's region attribute (empty: none)
  std::vector<int> faces;         // 3 nodes per boundary face
  std::vector<int> face_markers;  // the face's facet marker (empty: none)
};

/// Writes all of `bytes` to `fd`; false when the reader is gone.
bool write_all(int fd, const void* bytes, std::size_t n) {
  const char* p = static_cast<const char*>(bytes);
  while (n > 0) {
    const ssize_t w = write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

/// The child's side: TetGen's output arrays behind a header of their lengths.
bool send_output(int fd, const tetgenio& out) {
  const int attributes = out.numberoftetrahedronattributes;
  const std::array<std::int64_t, 5> lengths = {
      3 * std::int64_t{out.numberofpoints}, 4 * std::int64_t{out.numberoftetrahedra},
      attributes > 0 ? std::int64_t{out.numberoftetrahedra} : 0, 3 * std::int64_t{out.numberoftrifaces},
      out.trifacemarkerlist ? std::int64_t{out.numberoftrifaces} : 0};
  std::vector<int> tets(static_cast<std::size_t>(lengths[1]));
  for (std::size_t t = 0; t < tets.size() / 4; ++t)
    for (std::size_t k = 0; k < 4; ++k)
      tets[4 * t + k] = out.tetrahedronlist[static_cast<std::size_t>(out.numberofcorners) * t + k];
  std::vector<double> region(static_cast<std::size_t>(lengths[2]));
  for (std::size_t t = 0; t < region.size(); ++t)
    region[t] = out.tetrahedronattributelist[static_cast<std::size_t>(attributes) * t];
  return write_all(fd, lengths.data(), sizeof lengths) &&
         write_all(fd, out.pointlist, static_cast<std::size_t>(lengths[0]) * sizeof(double)) &&
         write_all(fd, tets.data(), tets.size() * sizeof(int)) &&
         write_all(fd, region.data(), region.size() * sizeof(double)) &&
         write_all(fd, out.trifacelist, static_cast<std::size_t>(lengths[3]) * sizeof(int)) &&
         write_all(fd, out.trifacemarkerlist, static_cast<std::size_t>(lengths[4]) * sizeof(int));
}

/// The parent's side: the arrays back from what the child sent, or nullopt when it sent
/// less or other than its header announced (a child that died while writing).
std::optional<MeshOutput> parse_output(const std::vector<char>& bytes) {
  std::array<std::int64_t, 5> lengths{};
  if (bytes.size() < sizeof lengths) return std::nullopt;
  std::memcpy(lengths.data(), bytes.data(), sizeof lengths);
  std::size_t at = sizeof lengths;
  bool whole = true;
  auto take = [&](auto& v, std::int64_t n) {
    using T = typename std::remove_reference_t<decltype(v)>::value_type;
    if (!whole || n < 0 || static_cast<std::size_t>(n) > (bytes.size() - at) / sizeof(T)) {
      whole = false;
      return;
    }
    v.resize(static_cast<std::size_t>(n));
    // An empty vector's data() may be null, and memcpy from or to null is undefined even for
    // zero bytes (the intersection check's run sends no tets).
    if (v.empty()) return;
    std::memcpy(v.data(), bytes.data() + at, v.size() * sizeof(T));
    at += v.size() * sizeof(T);
  };
  MeshOutput o;
  take(o.points, lengths[0]);
  take(o.tets, lengths[1]);
  take(o.region, lengths[2]);
  take(o.faces, lengths[3]);
  take(o.face_markers, lengths[4]);
  if (!whole || at != bytes.size()) return std::nullopt;
  return o;
}

struct ChildOutcome {
  int code = 0;  // TetGen's error code; -1: the child crashed or sent a broken answer
  MeshOutput output;
};

/// Meshes in a child process and reads the mesh back through a pipe. Debian's libtet 1.5
/// frees its pools twice on its error path and crashes instead of throwing, so TetGen never
/// runs in this process; and TetGen has no way to be interrupted, so `cancel` kills the
/// child, which takes its memory and its core with it. One TetGen run per mesh: a bad
/// complex is told by the child's exit code, not by a second surface-recovery run before.
ChildOutcome mesh_in_child(const Plc& plc, const std::string& switches, const std::atomic<bool>* cancel) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
    throw GeometryError(fmt::format("TetGen: cannot open a pipe to its process: {}", std::strerror(errno)));
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    throw GeometryError(fmt::format("TetGen: cannot start its process: {}", std::strerror(errno)));
  }
  if (pid == 0) {
    close(fds[0]);
    int code = 0;
    try {
      tetgenio in, out;
      fill_input(plc, in);
      std::vector<char> sw(switches.begin(), switches.end());
      sw.push_back('\0');
      ::tetrahedralize(sw.data(), &in, &out);
      if (!send_output(fds[1], out)) code = 2;
    } catch (int c) {
      code = c == 0 ? 2 : c;
    } catch (...) {
      code = 2;
    }
    _exit(code);
  }
  close(fds[1]);
  // Reads until end of file; an end that never comes (another thread's child inherited the
  // write end while it was open) is ended by this child's exit, seen between polls.
  std::vector<char> bytes;
  std::array<char, 1 << 16> chunk{};
  bool exited = false;
  int status = 0;
  for (;;) {
    if (cancel && cancel->load()) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      close(fds[0]);
      throw tocd::Cancelled("prediction cancelled while TetGen was meshing");
    }
    pollfd waiting{fds[0], POLLIN, 0};
    const int ready = poll(&waiting, 1, 20);
    if (ready > 0) {
      const ssize_t got = read(fds[0], chunk.data(), chunk.size());
      if (got > 0) {
        bytes.insert(bytes.end(), chunk.data(), chunk.data() + got);
        continue;
      }
      if (got == 0) break;
      if (errno == EINTR || errno == EAGAIN) continue;
      break;
    }
    if (ready < 0 && errno != EINTR) break;
    if (exited) break;  // nothing more came after the child's exit
    exited = waitpid(pid, &status, WNOHANG) == pid;
  }
  close(fds[0]);
  if (!exited && waitpid(pid, &status, 0) != pid) status = 0;
  ChildOutcome outcome;
  if (!WIFEXITED(status)) {
    outcome.code = -1;
    return outcome;
  }
  outcome.code = WEXITSTATUS(status);
  if (outcome.code != 0) return outcome;
  std::optional<MeshOutput> parsed = parse_output(bytes);
  if (!parsed) {
    outcome.code = -1;
    return outcome;
  }
  outcome.output = std::move(*parsed);
  return outcome;
}

/// Reruns TetGen's intersection detection (in a child) and names the surfaces it reports.
std::string surfaces_at_fault(const Plc& plc, const Section& section) {
  std::set<int> surfaces;
  for (const int m : mesh_in_child(plc, "pdzQ", nullptr).output.face_markers) surfaces.insert(surface_of(m));
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
      code < 0 ? "TetGen's process ended without a mesh (as it does on self-intersecting or nearly touching "
                 "facets)"
               : code_meaning(code);
  throw GeometryError(
      fmt::format("TetGen rejected the composite geometry: {}{}", reason,
                  names.empty() ? std::string{} : fmt::format(" (surfaces involved: {})", names)));
}

/// Mirrors the mesh across the plane where coordinate `axis` is 0, whose faces carry
/// `marker`: every node off the plane gets its image, every tet and every face off the plane
/// its mirrored copy; the plane's faces, now between a tet and its image, are dropped. The
/// nodes of those faces are put exactly on the plane (a point TetGen placed in it may be off
/// by rounding), so each is its own image and the two halves share the plane's triangulation.
void mirror(MeshOutput& out, int axis, int marker) {
  const std::size_t nodes = out.points.size() / 3;
  std::vector<bool> on_plane(nodes, false);
  const std::size_t faces = out.faces.size() / 3;
  for (std::size_t f = 0; f < faces; ++f)
    if (out.face_markers[f] == marker)
      for (std::size_t k = 0; k < 3; ++k) on_plane[static_cast<std::size_t>(out.faces[3 * f + k])] = true;
  std::vector<int> image(nodes);
  out.points.reserve(6 * nodes);
  for (std::size_t i = 0; i < nodes; ++i) {
    if (on_plane[i]) {
      out.points[3 * i + static_cast<std::size_t>(axis)] = 0.0;
      image[i] = static_cast<int>(i);
      continue;
    }
    image[i] = static_cast<int>(out.points.size() / 3);
    for (std::size_t k = 0; k < 3; ++k)
      out.points.push_back(k == static_cast<std::size_t>(axis) ? -out.points[3 * i + k]
                                                               : out.points[3 * i + k]);
  }
  const auto at = [&](int node) { return image[static_cast<std::size_t>(node)]; };
  const std::size_t tets = out.tets.size() / 4;
  out.tets.reserve(8 * tets);
  for (std::size_t t = 0; t < tets; ++t) {
    // Two corners swapped: a mirror turns a tet's orientation over.
    const std::array<int, 4> copy{at(out.tets[4 * t]), at(out.tets[4 * t + 1]), at(out.tets[4 * t + 3]),
                                  at(out.tets[4 * t + 2])};
    out.tets.insert(out.tets.end(), copy.begin(), copy.end());
  }
  if (!out.region.empty())
    for (std::size_t t = 0; t < tets; ++t) out.region.push_back(out.region[t]);
  std::vector<int> kept_faces, kept_markers;
  for (const bool image_side : {false, true})
    for (std::size_t f = 0; f < faces; ++f) {
      if (out.face_markers[f] == marker) continue;
      const int* v = &out.faces[3 * f];
      if (!image_side)
        kept_faces.insert(kept_faces.end(), {v[0], v[1], v[2]});
      else
        kept_faces.insert(kept_faces.end(), {at(v[0]), at(v[2]), at(v[1])});
      kept_markers.push_back(out.face_markers[f]);
    }
  out.faces = std::move(kept_faces);
  out.face_markers = std::move(kept_markers);
}

tocd::sim::mesh::TetMesh to_tet_mesh(const MeshOutput& out, const Section& section) {
  tocd::sim::mesh::TetMesh mesh;
  mesh.nodes.resize(out.points.size() / 3);
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i)
    mesh.nodes[i] = {out.points[3 * i], out.points[3 * i + 1], out.points[3 * i + 2]};
  const std::size_t nt = out.tets.size() / 4;
  mesh.tets.resize(nt);
  mesh.regions.resize(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    auto& tet = mesh.tets[t];
    for (std::size_t k = 0; k < 4; ++k) tet[k] = out.tets[4 * t + k];
    if (tocd::sim::mesh::signed_volume(mesh.nodes[tet[0]], mesh.nodes[tet[1]], mesh.nodes[tet[2]],
                                       mesh.nodes[tet[3]]) < 0)
      std::swap(tet[2], tet[3]);
    mesh.regions[t] = out.region.empty() ? 0 : static_cast<std::int32_t>(out.region[t]);
  }
  for (std::size_t f = 0; f < out.faces.size() / 3; ++f) {
    const int surface = out.face_markers.empty() ? -1 : surface_of(out.face_markers[f]);
    if (surface < 0 || surface >= static_cast<int>(section.surfaces.size())) continue;
    const int marker = section.surfaces[static_cast<std::size_t>(surface)].boundary_marker;
    if (marker <= 0) continue;
    mesh.boundary_faces.push_back({{out.faces[3 * f], out.faces[3 * f + 1], out.faces[3 * f + 2]}, marker});
  }
  return mesh;
}

}  // namespace

tocd::sim::mesh::TetMesh tetrahedralize(const Plc& plc, const Section& section, const std::string& switches,
                                        const std::atomic<bool>* cancel) {
  // z: 0-based output; A: region attributes from the seeds.
  ChildOutcome outcome = mesh_in_child(plc, switches + "zA", cancel);
  if (outcome.code != 0) reject(outcome.code, plc, section);
  if (plc.quadrant) {
    if (outcome.output.face_markers.size() * 3 != outcome.output.faces.size())
      throw GeometryError(
          "TetGen's quadrant mesh came back without face markers: its symmetry planes are unknown");
    mirror(outcome.output, 0, marker_of(kSymmetryPlaneX));
    mirror(outcome.output, 1, marker_of(kSymmetryPlaneY));
  }
  return to_tet_mesh(outcome.output, section);
}

}  // namespace tocd::sim::geometry::detail

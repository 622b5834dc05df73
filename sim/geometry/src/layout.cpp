#include "layout.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "pin_shape.hpp"

namespace tocd::sim::geometry::detail {

namespace {

// Fractions of the box half-width and of the edge length that set the tolerances below.
constexpr double kCoreFraction = 0.9;     // revolved part: r <= 0.9 * half width
constexpr double kFlatTolerance = 2e-4;   // mm: skin top this close to the undeformed top is flat
constexpr double kMaxEndMismatch = 0.25;  // mm: largest end-of-profile offset that is ramped out
constexpr double kRampWidth = 1.0;        // mm: width of that ramp
constexpr double kMaxPenetration = 0.1;   // mm: deeper skin-in-pin penetration is an error
constexpr double kCheckTolerance = 1e-6;  // mm: closest allowed approach of distinct surfaces
// Douglas-Peucker tolerance of compressed outlines, in section edges (0.02 mm): the FE
// outline is an element-edge staircase.
constexpr double kOutlineSimplify = 0.1;
// Outline points closer to the skin top than this many section edges (0.1 mm) right after
// the outline leaves it are dropped. Where the FE outline runs just under the pin/skin
// contact, its steps would leave native-skin slivers ~0.05 mm thick that TetGen fills with
// tiny tets (0.6 M at 1.5 mm).
constexpr double kNearSurface = 0.5;
// Skin points closer to the pin than this many section edges (10 um) are in contact. The FE
// skin leaves the pin tangentially; a smaller tolerance leaves an air wedge a few um thick
// over a whole segment, which TetGen fills with tiny tets (0.6 M at 1.25 mm with 2 %). The
// flat skin at d = 0 stays a point contact (its first point is 13 um below the tip's facet).
constexpr double kContactFraction = 0.05;

std::string at(Vec2 p) {
  return fmt::format("(r = {:.4f} mm, z = {:.4f} mm)", p.r, p.z);
}

bool finite(Vec2 p) {
  return std::isfinite(p.r) && std::isfinite(p.z);
}

/// Number of equal segments of at most about `step` (1e-9 slack) that cover `length`.
int segment_count(double length, double step) {
  return std::max(1, static_cast<int>(std::ceil(length / step - 1e-9)));
}

/// Cumulative arc length of a polyline.
std::vector<double> arc_lengths(const std::vector<Vec2>& line) {
  std::vector<double> s(line.size(), 0.0);
  for (std::size_t i = 1; i < line.size(); ++i) s[i] = s[i - 1] + norm(line[i] - line[i - 1]);
  return s;
}

Vec2 at_arc(const std::vector<Vec2>& line, const std::vector<double>& s, double si) {
  if (si <= 0) return line.front();
  if (si >= s.back()) return line.back();
  const auto it = std::upper_bound(s.begin(), s.end(), si);
  const std::size_t j = static_cast<std::size_t>(it - s.begin());
  const double f = (si - s[j - 1]) / std::max(s[j] - s[j - 1], 1e-300);
  return line[j - 1] + f * (line[j] - line[j - 1]);
}

/// Distance from p to a polyline and the arc parameter of the closest point.
double polyline_distance(const std::vector<Vec2>& line, const std::vector<double>& s, Vec2 p, double* arc) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    double t = 0;
    const double d = segment_distance(p, line[i], line[i + 1], &t);
    if (d < best) {
      best = d;
      *arc = s[i] + t * (s[i + 1] - s[i]);
    }
  }
  return best;
}

/// Height of the skin top above r (the outermost segment spanning r), for inside checks.
double surface_height(const std::vector<Vec2>& line, double r) {
  for (std::size_t i = line.size() - 1; i > 0; --i) {
    const Vec2 a = line[i - 1], b = line[i];
    if (a.r <= r && r <= b.r && b.r > a.r) return a.z + (r - a.r) / (b.r - a.r) * (b.z - a.z);
  }
  return line.back().z;
}

/// The FE top surface, checked, trimmed to the revolved core and ending exactly on the
/// undeformed top. An empty profile is flat skin.
std::vector<Vec2> prepare_top_surface(const SkinProfile& skin, double r_core) {
  const std::string name = "skin top surface";
  const double t = skin.thickness_mm;
  std::vector<Vec2> p;
  for (std::size_t i = 0; i < skin.top_surface.size(); ++i) {
    const Vec2 q{skin.top_surface[i].r_mm, skin.top_surface[i].z_mm};
    if (!finite(q)) throw GeometryError(fmt::format("{}: point {} is not a finite number", name, i));
    if (!p.empty() && q.r < p.back().r - 1e-9)
      throw GeometryError(
          fmt::format("{}: not ordered outwards, r decreases from {:.4f} to {:.4f} mm at point {}", name,
                      p.back().r, q.r, i));
    if (q.z <= 1e-3)
      throw GeometryError(
          fmt::format("{}: point {} at {} reaches the slide (no skin left under it)", name, i, at(q)));
    if (!p.empty() && norm(q - p.back()) < 1e-9) continue;
    p.push_back(q);
  }
  if (p.empty()) return {{0, t}, {r_core, t}};
  if (p.size() < 2) throw GeometryError(fmt::format("{}: needs at least two points, got one", name));
  if (p.front().r > 1e-6)
    throw GeometryError(
        fmt::format("{}: must start on the pin axis (r = 0), starts at {}", name, at(p.front())));
  p.front().r = 0;
  // Trim at the core radius: the skin is flat beyond it (the deformed zone of the pin
  // model is well inside 0.9 of the 6.25 mm half width).
  if (p.back().r > r_core) {
    std::vector<Vec2> trimmed;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p[i].r <= r_core) {
        trimmed.push_back(p[i]);
        continue;
      }
      const Vec2 a = p[i - 1], b = p[i];
      trimmed.push_back({r_core, a.z + (r_core - a.r) / (b.r - a.r) * (b.z - a.z)});
      break;
    }
    p = trimmed;
  }
  // Ramp out the last point's offset from the undeformed top over the last millimetre so the
  // revolved surface meets the flat skin without a step.
  const double end_offset = t - p.back().z;
  if (std::abs(end_offset) > kMaxEndMismatch)
    throw GeometryError(
        fmt::format("{}: ends at {}, {:.3f} mm from the undeformed top z = {:.3f} mm; the profile "
                    "must reach the flat skin",
                    name, at(p.back()), end_offset, t));
  const double r_end = p.back().r;
  const double width = std::min(kRampWidth, r_end);
  for (auto& q : p)
    if (width > 0) q.z += end_offset * std::clamp((q.r - (r_end - width)) / width, 0.0, 1.0);
  p.back().z = t;
  for (auto& q : p)
    if (std::abs(q.z - t) <= kFlatTolerance) q.z = t;
  if (p.back().r < r_core - 1e-9) p.push_back({r_core, t});
  return p;
}

struct OutlineVertex {
  Vec2 p;
  bool on_surface = false, on_axis = false, on_slide = false;
  double arc = 0;  // on the top surface
};

enum class EdgeKind { surface, axis, slide, chain };

class LayoutBuilder {
 public:
  LayoutBuilder(const CompositeSpec& spec, double edge, double tip_edge)
      : spec_(spec), h_(edge), h_tip_(tip_edge) {}

  Layout build() {
    check_spec();
    auto& s = L_.section;
    s.add_surface("slide bottom face", slide_bottom);
    s.add_surface("slide side faces", slide_sides);
    s.add_surface("air top face", top);
    s.add_surface("pin top face", pin_top);
    s.add_surface("skin side faces", skin_sides);
    s.add_surface("air side faces", air_sides);
    s.add_surface("slide top surface", 0);
    s.add_surface("flat skin top surface", 0);
    s.add_surface("skin top surface", 0);
    s.add_surface("pin/skin contact surface", 0);
    s.add_surface("glass pin surface", 0);
    if (spec_.baseline)
      build_baseline();
    else
      build_skin();
    add_slide_plane();
    check_section(s, kCheckTolerance);
    return std::move(L_);
  }

 private:
  void check_spec() {
    const auto positive = [](double v, const char* what) {
      if (!std::isfinite(v) || v <= 0)
        throw GeometryError(fmt::format("composite: {} must be positive, got {}", what, v));
    };
    positive(spec_.slide_size_mm, "slide_size_mm");
    positive(spec_.slide_thickness_mm, "slide_thickness_mm");
    positive(spec_.skin_size_mm, "skin_size_mm");
    positive(spec_.pin_radius_mm, "pin_radius_mm");
    positive(spec_.pin_length_mm, "pin_length_mm");
    if (!std::isfinite(spec_.pin_displacement_mm) || spec_.pin_displacement_mm < 0)
      throw GeometryError(
          fmt::format("composite: pin_displacement_mm must be >= 0, got {}", spec_.pin_displacement_mm));
    if (std::abs(spec_.skin_size_mm - spec_.slide_size_mm) > 1e-9)
      throw GeometryError(
          fmt::format("composite: skin_size_mm ({}) must equal slide_size_mm ({}): the skin covers the "
                      "whole slide",
                      spec_.skin_size_mm, spec_.slide_size_mm));
    if (spec_.pin_length_mm <= spec_.pin_radius_mm)
      throw GeometryError(fmt::format("glass pin: length {} mm must exceed its tip radius {} mm",
                                      spec_.pin_length_mm, spec_.pin_radius_mm));
    L_.half_mm = 0.5 * spec_.slide_size_mm;
    L_.r_core_mm = kCoreFraction * L_.half_mm;
    if (spec_.pin_radius_mm + h_ > L_.r_core_mm)
      throw GeometryError(fmt::format("glass pin: radius {} mm does not fit in the {} mm box",
                                      spec_.pin_radius_mm, spec_.slide_size_mm));
    L_.slide_thickness_mm = spec_.slide_thickness_mm;
    L_.baseline = spec_.baseline;
    if (!spec_.baseline) {
      positive(spec_.skin.thickness_mm, "skin thickness_mm");
      if (spec_.pin_displacement_mm >= spec_.skin.thickness_mm)
        throw GeometryError(fmt::format("glass pin: displacement {} mm reaches through the {} mm skin",
                                        spec_.pin_displacement_mm, spec_.skin.thickness_mm));
    }
  }

  PinShape pin_shape(double tip_z) const {
    PinShape pin;
    pin.radius = spec_.pin_radius_mm;
    pin.tip_z = tip_z;
    pin.top_z = tip_z + spec_.pin_length_mm;
    return pin;
  }

  /// Adds the pin outline from its tip to (R, top): `anchors` are (u, vertex) pairs already
  /// in the section (contact points shared with the skin, in increasing u); the rest of the
  /// outline is sampled with arc steps of about the edge length.
  void add_pin(const PinShape& pin, std::vector<std::pair<double, int>> anchors) {
    auto& s = L_.section;
    if (anchors.empty() || anchors.front().first > 1e-12)
      anchors.insert(anchors.begin(), {0.0, s.add_vertex(pin.point(0))});
    anchors.push_back({pin.end_u(), s.add_vertex(pin.point(pin.end_u()))});
    std::vector<int> chain{anchors.front().second};
    std::vector<bool> shared{true};
    for (std::size_t k = 0; k + 1 < anchors.size(); ++k) {
      const double u0 = anchors[k].first, u1 = anchors[k + 1].first;
      if (s.has_edge(anchors[k].second, anchors[k + 1].second)) {
        // Neighbours on the skin top: the contact edge between them is the pin's outline
        // there. A pin vertex between them would leave a sliver of air under the chord.
        chain.push_back(anchors[k + 1].second);
        continue;
      }
      // Break at the equator so the hemisphere and cylinder each get exact vertices.
      std::vector<double> breaks{u0};
      // A free apex (touching the slide or the skin at one point, as on the rigid slide of the
      // baseline) keeps a section-edge first segment: finer facets there would lie within a
      // degree of the plane the apex touches, an air wedge TetGen cannot recover. Light meets
      // the apex near normal incidence, where the facets' tilt hardly matters; the tip's steps
      // matter towards the critical angle.
      const bool free_apex = u0 == 0.0 && h_tip_ < h_ && h_ < u1;
      if (free_apex) breaks.push_back(h_);
      if (u0 < pin.equator_u() - 1e-9 && pin.equator_u() < u1 - 1e-9) breaks.push_back(pin.equator_u());
      breaks.push_back(u1);
      for (std::size_t b = 0; b + 1 < breaks.size(); ++b) {
        const double step = breaks[b] < pin.equator_u() - 1e-9 && !(free_apex && b == 0) ? h_tip_ : h_;
        const int n = segment_count(breaks[b + 1] - breaks[b], step);
        for (int i = 1; i <= n; ++i) {
          const bool last = b + 2 == breaks.size() && i == n;
          if (last) {
            chain.push_back(anchors[k + 1].second);
          } else {
            chain.push_back(s.add_vertex(pin.point(breaks[b] + (breaks[b + 1] - breaks[b]) * i / n)));
          }
        }
      }
    }
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
      // Edges between two contact points that are neighbours on the skin top already exist
      // (as contact edges); add_edge skips them.
      s.add_edge(chain[i], chain[i + 1], kPinSurface);
    }
    L_.pin_top_vertex = chain.back();
    for (int id : chain) L_.pin_polygon.push_back(s.vertices[static_cast<std::size_t>(id)]);
    L_.pin_polygon.push_back({0, pin.top_z});
    L_.z_top_mm = pin.top_z;
  }

  void build_baseline() {
    L_.skin_top_mm = 0;
    add_pin(pin_shape(0.0), {});
  }

  void build_skin() {
    const double t = spec_.skin.thickness_mm;
    L_.skin_top_mm = t;
    L_.planes.push_back({t, kSkinFlatTop});
    const PinShape pin = pin_shape(t - spec_.pin_displacement_mm);
    fe_top_ = prepare_top_surface(spec_.skin, L_.r_core_mm);
    fe_arc_ = arc_lengths(fe_top_);
    for (const auto& q : fe_top_)
      if (q.z >= pin.top_z - h_)
        throw GeometryError(
            fmt::format("skin top surface reaches the air's top face at {} (pin length {} mm too short)",
                        at(q), spec_.pin_length_mm));

    // Compressed outlines first: where they meet the skin top, the top needs vertices.
    std::vector<std::vector<OutlineVertex>> outlines;
    std::vector<double> breaks{0.0, fe_arc_.back()};
    for (std::size_t k = 0; k < spec_.skin.compressed_outlines.size(); ++k) {
      outlines.push_back(classify_outline(k));
      // Only where the outline leaves the surface does the skin top need a vertex.
      const auto& v = outlines.back();
      for (std::size_t i = 0; i < v.size(); ++i) {
        const EdgeKind before = edge_kind(v[(i + v.size() - 1) % v.size()], v[i]);
        const EdgeKind after = edge_kind(v[i], v[(i + 1) % v.size()]);
        if (v[i].on_surface && !(before == EdgeKind::surface && after == EdgeKind::surface))
          breaks.push_back(v[i].arc);
      }
    }
    // Under the pin the skin top takes the tip's finer steps: its points there become the
    // contact surface, and where pin and skin part their spacing sets the air wedge's angle.
    const double under_pin_arc = arc_at_radius(pin.radius);
    breaks.push_back(under_pin_arc);
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end(), [](double a, double b) { return b - a < 1e-9; }),
                 breaks.end());

    // Skin top: the FE polyline resampled with steps of about the edge length.
    std::vector<Vec2> top;
    std::vector<double> top_arc;
    for (std::size_t b = 0; b + 1 < breaks.size(); ++b) {
      const double step = breaks[b] < under_pin_arc - 1e-9 ? h_tip_ : h_;
      const int n = segment_count(breaks[b + 1] - breaks[b], step);
      for (int i = (b == 0 ? 0 : 1); i <= n; ++i) {
        const double si = i == n ? breaks[b + 1] : breaks[b] + (breaks[b + 1] - breaks[b]) * i / n;
        top.push_back(at_arc(fe_top_, fe_arc_, si));
        top_arc.push_back(si);
      }
    }
    // Contact: skin points closer to the pin than a small tolerance are moved onto the pin
    // outline, so the contact surface is one revolved polyline shared by pin and skin. The
    // tolerance (kContactFraction of the edge, at least 2 um) also keeps the air wedge where pin and
    // skin separate from being thinner than TetGen can resolve.
    const double contact_tol = std::max(0.002, kContactFraction * h_);
    std::vector<std::pair<double, int>> anchors;
    std::vector<bool> contact(top.size(), false);
    auto& s = L_.section;
    top_ids_.resize(top.size());
    for (std::size_t i = 0; i < top.size(); ++i) {
      double u = 0, gap = 0;
      pin.project(top[i], &u, &gap);
      if (gap < -kMaxPenetration)
        throw GeometryError(
            fmt::format("skin top surface penetrates the glass pin by {:.3f} mm at {}", -gap, at(top[i])));
      if (gap < contact_tol && top[i].z < pin.top_z) {
        if (!anchors.empty() && u < anchors.back().first + 1e-9)
          throw GeometryError(
              fmt::format("skin top surface folds back along the glass pin at {}", at(top[i])));
        top[i] = pin.point(u);
        contact[i] = true;
        L_.contact_radius_mm = std::max(L_.contact_radius_mm, top[i].r);
      }
      top_ids_[i] = s.add_vertex(top[i]);
      if (contact[i]) anchors.push_back({u, top_ids_[i]});
      arc_to_id_[top_arc[i]] = top_ids_[i];
    }
    for (std::size_t i = 0; i + 1 < top.size(); ++i)
      s.add_edge(top_ids_[i], top_ids_[i + 1], contact[i] && contact[i + 1] ? kContact : kSkinTop);
    add_pin(pin, anchors);

    // The skin's depression below (or bulge above) its undeformed top, for volumes.
    L_.depression_polygon = top;
    L_.depression_polygon.push_back({0, t});
    L_.skin_polygon = top;
    L_.skin_polygon.push_back({top.back().r, 0});
    L_.skin_polygon.push_back({0, 0});
    for (std::size_t k = 0; k < outlines.size(); ++k) add_outline(k, outlines[k]);
  }

  /// Arc length along the skin top where it first reaches radius r (its end if it never does).
  double arc_at_radius(double r) const {
    for (std::size_t i = 0; i + 1 < fe_top_.size(); ++i) {
      const Vec2 a = fe_top_[i], b = fe_top_[i + 1];
      if (b.r >= r && b.r > a.r)
        return fe_arc_[i] + std::clamp((r - a.r) / (b.r - a.r), 0.0, 1.0) * (fe_arc_[i + 1] - fe_arc_[i]);
    }
    return fe_arc_.back();
  }

  std::vector<OutlineVertex> classify_outline(std::size_t k) {
    const std::string name = fmt::format("compressed outline {}", k);
    const auto& in = spec_.skin.compressed_outlines[k];
    std::vector<Vec2> p;
    for (std::size_t i = 0; i < in.size(); ++i) {
      const Vec2 q{in[i].r_mm, in[i].z_mm};
      if (!finite(q)) throw GeometryError(fmt::format("{}: point {} is not a finite number", name, i));
      if (!p.empty() && norm(q - p.back()) < 1e-9) continue;
      p.push_back(q);
    }
    while (p.size() > 1 && norm(p.front() - p.back()) < 1e-9) p.pop_back();
    if (p.size() < 3)
      throw GeometryError(fmt::format("{}: needs at least 3 distinct points, got {}", name, p.size()));
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = i + 1; j < p.size(); ++j) {
        const std::size_t i1 = (i + 1) % p.size(), j1 = (j + 1) % p.size();
        if (j == i1 || i == j1) continue;
        if (segments_intersect(p[i], p[i1], p[j], p[j1]))
          throw GeometryError(fmt::format("{}: self-intersecting near {}", name, at(p[j])));
      }
    const double area2 = signed_area2(p);
    if (std::abs(area2) < 1e-10) throw GeometryError(fmt::format("{}: degenerate (zero area)", name));
    if (area2 < 0) std::reverse(p.begin(), p.end());

    const double tol = std::max(1e-4, 0.005 * h_);
    std::vector<OutlineVertex> out;
    for (const auto& q : p) {
      OutlineVertex v;
      v.p = q;
      if (q.r < -tol || q.r > L_.r_core_mm)
        throw GeometryError(
            fmt::format("{}: point {} lies outside the revolved part of the skin (0 <= r <= {:.3f} mm)", name,
                        at(q), L_.r_core_mm));
      if (q.z < -tol || q.z > surface_height(fe_top_, q.r) + tol)
        throw GeometryError(fmt::format("{}: point {} lies outside the skin", name, at(q)));
      v.on_surface = polyline_distance(fe_top_, fe_arc_, q, &v.arc) <= tol;
      v.on_axis = q.r <= tol;
      v.on_slide = q.z <= tol;
      out.push_back(v);
    }
    return out;
  }

  EdgeKind edge_kind(const OutlineVertex& a, const OutlineVertex& b) const {
    const Vec2 mid = 0.5 * (a.p + b.p);
    double arc = 0;
    const double tol = std::max(1e-4, 0.005 * h_);
    if (a.on_surface && b.on_surface && polyline_distance(fe_top_, fe_arc_, mid, &arc) <= tol)
      return EdgeKind::surface;
    if (a.on_axis && b.on_axis) return EdgeKind::axis;
    if (a.on_slide && b.on_slide) return EdgeKind::slide;
    return EdgeKind::chain;
  }

  void add_outline(std::size_t k, const std::vector<OutlineVertex>& v) {
    const std::size_t n = v.size();
    auto& s = L_.section;
    const int surface = s.add_surface(fmt::format("compressed outline {}", k), 0);
    std::vector<EdgeKind> kind(n);
    for (std::size_t i = 0; i < n; ++i) kind[i] = edge_kind(v[i], v[(i + 1) % n]);
    if (std::all_of(kind.begin(), kind.end(), [](EdgeKind e) { return e != EdgeKind::chain; }))
      throw GeometryError(
          fmt::format("compressed outline {}: lies along the skin's boundary, encloses no skin", k));
    // A vertex inside a run of boundary edges of one kind is dropped: the boundary itself is
    // the interface there.
    std::vector<bool> keep(n, true);
    for (std::size_t i = 0; i < n; ++i) {
      const EdgeKind before = kind[(i + n - 1) % n], after = kind[i];
      if (before == after && after != EdgeKind::chain) keep[i] = false;
    }
    // Simplify runs of interior (chain) edges: the FE outline follows element edges (a
    // staircase); see kOutlineSimplify.
    std::size_t start = 0;
    while (start < n && !(keep[start] && kind[(start + n - 1) % n] != EdgeKind::chain)) ++start;
    if (start == n) {
      // A closed loop of chain edges: simplify two halves.
      simplify_run(v, keep, 0, n / 2, n);
      simplify_run(v, keep, n / 2, n, n);
    } else {
      for (std::size_t i = start, steps = 0; steps < n;) {
        std::size_t j = i, m = 0;
        while (kind[j % n] == EdgeKind::chain && m < n) {
          ++j;
          ++m;
        }
        if (m > 1) simplify_run(v, keep, i, i + m, n);
        const std::size_t advance = std::max<std::size_t>(m, 1);
        i = (i + advance) % n;
        steps += advance;
      }
    }
    // Section vertices of the kept points, and the closed polygon (with the skin top's own
    // vertices along the stretches where the outline runs on the surface).
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i]) kept.push_back(i);
    std::vector<int> ids(n, -1);
    for (std::size_t i : kept) ids[i] = vertex_for(v[i]);
    std::vector<int> polygon;
    for (std::size_t a = 0; a < kept.size(); ++a) {
      const std::size_t i = kept[a], j = kept[(a + 1) % kept.size()];
      polygon.push_back(ids[i]);
      if (kind[i] == EdgeKind::surface) {
        for (int id : top_between(v[i].arc, v[j].arc)) polygon.push_back(id);
      }
    }
    std::vector<Vec2> shape;
    for (std::size_t a = 0; a < polygon.size(); ++a) {
      const int p = polygon[a], q = polygon[(a + 1) % polygon.size()];
      shape.push_back(s.vertices[static_cast<std::size_t>(p)]);
      const Vec2 P = s.vertices[static_cast<std::size_t>(p)], Q = s.vertices[static_cast<std::size_t>(q)];
      if (s.has_edge(p, q)) continue;      // runs along the skin top: shared edge
      if (P.r == 0 && Q.r == 0) continue;  // along the axis: nothing to revolve
      if (P.z == 0 && Q.z == 0) continue;  // on the slide: part of the slide's top facet
      s.add_edge(p, q, surface);
    }
    if (signed_area2(shape) <= 0)
      throw GeometryError(
          fmt::format("compressed outline {}: degenerate after fitting it to the skin's boundary", k));
    L_.compressed_polygons.push_back(shape);
  }

  void simplify_run(const std::vector<OutlineVertex>& v, std::vector<bool>& keep, std::size_t from,
                    std::size_t to, std::size_t n) {
    // Where the run leaves the skin top, the interior points that follow it just under the
    // surface are dropped first, as long as the run reaches deeper: see kNearSurface.
    const auto near = [&](std::size_t i) {
      double arc = 0;
      return polyline_distance(fe_top_, fe_arc_, v[i % n].p, &arc) < kNearSurface * h_;
    };
    std::size_t first = from + 1, last = to;  // interior points kept: [first, last)
    if (v[from % n].on_surface)
      while (first < last && near(first)) ++first;
    if (v[to % n].on_surface)
      while (last > first && near(last - 1)) --last;
    if (first == last) first = from + 1, last = to;  // nothing deeper: keep them all
    std::vector<bool> drop(to - from + 1, false);
    for (std::size_t i = from + 1; i < to; ++i) drop[i - from] = i < first || i >= last;
    std::vector<Vec2> line;
    std::vector<std::size_t> index;
    for (std::size_t i = from; i <= to; ++i) {
      if (drop[i - from]) {
        keep[i % n] = false;
        continue;
      }
      line.push_back(v[i % n].p);
      index.push_back(i % n);
    }
    const auto simple = simplify(line, kOutlineSimplify * h_);
    for (std::size_t i = 1; i + 1 < line.size(); ++i) {
      const bool in = std::any_of(simple.begin(), simple.end(),
                                  [&](Vec2 q) { return q.r == line[i].r && q.z == line[i].z; });
      if (!in) keep[index[i]] = false;
    }
  }

  int vertex_for(const OutlineVertex& v) {
    if (v.on_surface) {
      const auto it = arc_to_id_.lower_bound(v.arc - 1e-8);
      if (it != arc_to_id_.end() && it->first <= v.arc + 1e-8) return it->second;
    }
    Vec2 p = v.p;
    if (v.on_axis) p.r = 0;
    if (v.on_slide) p.z = 0;
    auto& s = L_.section;
    for (std::size_t i = 0; i < s.vertices.size(); ++i)
      if (norm(s.vertices[i] - p) < 1e-9) return static_cast<int>(i);
    return s.add_vertex(p);
  }

  /// Skin-top vertices strictly between two arc positions, in walking order from a to b.
  std::vector<int> top_between(double a, double b) const {
    std::vector<int> ids;
    if (a < b) {
      for (auto it = arc_to_id_.upper_bound(a); it != arc_to_id_.end() && it->first < b; ++it)
        ids.push_back(it->second);
    } else {
      for (auto it = arc_to_id_.upper_bound(b); it != arc_to_id_.end() && it->first < a; ++it)
        ids.push_back(it->second);
      std::reverse(ids.begin(), ids.end());
    }
    return ids;
  }

  /// The slide's top plane is covered everywhere: split it at every vertex that lies on it.
  void add_slide_plane() {
    auto& s = L_.section;
    L_.planes.push_back({0.0, kSlideTop});
    std::vector<int> on;
    for (std::size_t i = 0; i < s.vertices.size(); ++i)
      if (s.vertices[i].z == 0) on.push_back(static_cast<int>(i));
    const auto ensure = [&](double r) {
      for (int id : on)
        if (s.vertices[static_cast<std::size_t>(id)].r == r) return;
      on.push_back(s.add_vertex({r, 0}));
    };
    ensure(0);
    ensure(L_.r_core_mm);
    std::sort(on.begin(), on.end(), [&](int a, int b) {
      return s.vertices[static_cast<std::size_t>(a)].r < s.vertices[static_cast<std::size_t>(b)].r;
    });
    for (std::size_t i = 0; i + 1 < on.size(); ++i) s.add_edge(on[i], on[i + 1], kSlideTop);
  }

  const CompositeSpec& spec_;
  double h_;
  double h_tip_;  // segment length of the pin's hemispherical tip and the skin top under it
  Layout L_;
  std::vector<Vec2> fe_top_;
  std::vector<double> fe_arc_;
  std::vector<int> top_ids_;
  std::map<double, int> arc_to_id_;
};

}  // namespace

int plane_of_edge(const Layout& layout, const Section::Edge& e) {
  const Vec2 a = layout.section.vertices[static_cast<std::size_t>(e.a)];
  const Vec2 b = layout.section.vertices[static_cast<std::size_t>(e.b)];
  for (std::size_t i = 0; i < layout.planes.size(); ++i)
    if (a.z == layout.planes[i].z && b.z == layout.planes[i].z) return static_cast<int>(i);
  return -1;
}

Layout build_layout(const CompositeSpec& spec, double section_edge_mm, double tip_edge_mm) {
  return LayoutBuilder(spec, section_edge_mm, tip_edge_mm).build();
}

}  // namespace tocd::sim::geometry::detail

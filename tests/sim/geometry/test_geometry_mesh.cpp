// The composite mesh is conforming, its regions have the volumes of the geometry they
// mesh, and its outer faces carry the right markers.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>

#include <gtest/gtest.h>

#include "mesh_cache.hpp"
#include "tocd/sim/mesh/topology.hpp"

namespace geo = tocd::sim::geometry;
namespace mesh = tocd::sim::mesh;
using geo::testing::Case;

namespace {

const std::vector<Case> kAllCases{Case::baseline,
                                  Case::flat,
                                  Case::indent_05,
                                  Case::indent_10,
                                  Case::indent_15,
                                  Case::indent_15_on_slide,
                                  Case::indent_10_native_pocket,
                                  Case::fe_d10_h20};

std::string name_of(Case c) {
  switch (c) {
    case Case::baseline:
      return "baseline";
    case Case::flat:
      return "flat";
    case Case::indent_05:
      return "indent_05";
    case Case::indent_10:
      return "indent_10";
    case Case::indent_15:
      return "indent_15";
    case Case::indent_15_on_slide:
      return "indent_15_on_slide";
    case Case::indent_10_native_pocket:
      return "indent_10_native_pocket";
    case Case::fe_d10_h20:
      return "fe_d10_h20";
  }
  return "?";
}

const geo::RegionStats* stats(const geo::CompositeMesh& m, int region) {
  for (const auto& r : m.regions)
    if (r.region == region) return &r;
  return nullptr;
}

// 2 pi int r dA of a closed r-z polygon by the shoelace-style centroid formula (written
// independently of the library's Green-theorem version).
double revolved_volume(const std::vector<geo::ProfilePoint>& p) {
  double area2 = 0, moment6 = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& a = p[i];
    const auto& b = p[(i + 1) % p.size()];
    const double c = a.r_mm * b.z_mm - b.r_mm * a.z_mm;
    area2 += c;
    moment6 += (a.r_mm + b.r_mm) * c;
  }
  const double area = 0.5 * area2, centroid_r = moment6 / (3.0 * area2);
  return std::abs(2.0 * std::numbers::pi * centroid_r * area);
}

class CompositeCase : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(CompositeCase, MeshIsConforming) {
  const auto& m = geo::testing::mesh_of(GetParam());
  // validate: no inverted tets, no face shared by more than two tets, no hanging nodes.
  const mesh::FaceAdjacency adj = mesh::validate(m.mesh);
  // Every face with one tet lies on the outer box: no gaps inside the composite.
  const auto box = mesh::bounding_box(m.mesh);
  std::size_t boundary = 0;
  for (std::size_t t = 0; t < m.mesh.tets.size(); ++t) {
    for (int f = 0; f < 4; ++f) {
      if (adj.neighbour[t][f] >= 0) continue;
      ++boundary;
      for (int k : mesh::kFaceLocalNodes[f]) {
        const auto& x = m.mesh.nodes[m.mesh.tets[t][k]];
        bool on_box = false;
        for (int a = 0; a < 3; ++a)
          on_box = on_box || std::abs(x[a] - box.min[a]) < 1e-9 || std::abs(x[a] - box.max[a]) < 1e-9;
        ASSERT_TRUE(on_box) << "tet " << t << " face " << f << " is open inside the composite";
      }
    }
  }
  EXPECT_EQ(boundary, m.mesh.boundary_faces.size());
}

// TetGen meshes one quadrant and the mesher mirrors it across x = 0 and y = 0: every node has
// its images among the nodes (a negation is exact), and every tet has its image tet (the same
// four image nodes) in the same region. A quadrant whose plane nodes were off the plane would
// leave unmatched images; one whose halves did not share them fails MeshIsConforming.
TEST_P(CompositeCase, MeshIsMirrorSymmetric) {
  const auto& m = geo::testing::mesh_of(GetParam());
  using Point = std::array<double, 3>;
  using Corners = std::array<std::size_t, 4>;
  std::map<Point, std::size_t> node_at;
  for (std::size_t i = 0; i < m.mesh.nodes.size(); ++i) node_at[m.mesh.nodes[i]] = i;
  std::map<Corners, std::int32_t> region_of;
  const auto sorted = [](Corners c) {
    std::sort(c.begin(), c.end());
    return c;
  };
  for (std::size_t t = 0; t < m.mesh.tets.size(); ++t) {
    const auto& v = m.mesh.tets[t];
    region_of[sorted({std::size_t(v[0]), std::size_t(v[1]), std::size_t(v[2]), std::size_t(v[3])})] =
        m.mesh.regions[t];
  }
  for (const Point sign : {Point{-1, 1, 1}, Point{1, -1, 1}}) {
    std::vector<std::size_t> image(m.mesh.nodes.size());
    for (std::size_t i = 0; i < m.mesh.nodes.size(); ++i) {
      const auto& x = m.mesh.nodes[i];
      const auto found = node_at.find({sign[0] * x[0], sign[1] * x[1], x[2]});
      ASSERT_NE(found, node_at.end()) << "no image of node (" << x[0] << ", " << x[1] << ", " << x[2] << ")";
      image[i] = found->second;
    }
    for (std::size_t t = 0; t < m.mesh.tets.size(); ++t) {
      const auto& v = m.mesh.tets[t];
      const auto found = region_of.find(sorted({image[std::size_t(v[0])], image[std::size_t(v[1])],
                                                image[std::size_t(v[2])], image[std::size_t(v[3])]}));
      ASSERT_NE(found, region_of.end()) << "no image of tet " << t;
      EXPECT_EQ(found->second, m.mesh.regions[t]) << "tet " << t;
    }
  }
}

TEST_P(CompositeCase, RegionVolumesMatchTheGeometry) {
  const auto& m = geo::testing::mesh_of(GetParam());
  for (const auto& r : m.regions) {
    EXPECT_GT(r.tets, 0u) << "region " << r.region;
    EXPECT_NEAR(r.volume_mm3, r.expected_volume_mm3, 0.01 * r.expected_volume_mm3) << "region " << r.region;
    EXPECT_NEAR(r.volume_mm3, mesh::region_volume(m.mesh, r.region), 1e-9 * r.volume_mm3);
  }
  // Independent references: the slide box exactly; the pin's continuous volume within the
  // N-gon (N = 64: 0.16 %) and chord (< 0.1 %) deficits of the revolved polygon.
  const auto spec = geo::testing::spec_of(GetParam());
  EXPECT_NEAR(stats(m, geo::slide)->expected_volume_mm3, 12.5 * 12.5 * 1.0, 1e-9);
  const double R = spec.pin_radius_mm, L = spec.pin_length_mm;
  const double pin = std::numbers::pi * R * R * (L - R) + 2.0 / 3.0 * std::numbers::pi * R * R * R;
  EXPECT_NEAR(stats(m, geo::pin)->expected_volume_mm3, pin * 0.998, 0.002 * pin);
  double total = 0;
  for (const auto& r : m.regions) total += r.volume_mm3;
  const double z_top = (spec.baseline ? 0.0 : spec.skin.thickness_mm - spec.pin_displacement_mm) + L;
  EXPECT_NEAR(total, 12.5 * 12.5 * (1.0 + z_top), 1e-6 * total);
  if (spec.baseline) {
    EXPECT_EQ(stats(m, geo::skin), nullptr);
    return;
  }
  if (spec.skin.compressed_outlines.empty()) {
    // Flat skin, but where it lies within the contact tolerance (10 um) of the pin's tip it
    // is lifted onto the pin: a bulge of at most that height over the contact disc.
    const double bulge = std::numbers::pi * m.contact_radius_mm * m.contact_radius_mm * 0.010;
    EXPECT_NEAR(stats(m, geo::skin)->expected_volume_mm3, 12.5 * 12.5 * spec.skin.thickness_mm, bulge + 1e-9);
    EXPECT_EQ(stats(m, geo::compressed), nullptr);
  } else {
    // The compressed zone as meshed against the FE outline's own revolved volume: within
    // the N-gon deficit and the outline's simplification (half a section edge).
    const double fe = revolved_volume(spec.skin.compressed_outlines[0]);
    EXPECT_NEAR(stats(m, geo::compressed)->volume_mm3, fe, 0.03 * fe);
  }
}

TEST_P(CompositeCase, OuterFacesCarryTheirMarkers) {
  const auto& m = geo::testing::mesh_of(GetParam());
  const auto spec = geo::testing::spec_of(GetParam());
  const double slide_top = spec.slide_thickness_mm;  // above the box bottom
  const double skin_top = spec.baseline ? 0.0 : spec.skin.thickness_mm;
  const auto box = mesh::bounding_box(m.mesh);
  std::map<int, int> count;
  for (const auto& f : m.mesh.boundary_faces) {
    ++count[f.marker];
    double zmin = 1e9, zmax = -1e9, rmax = 0, side = 0;
    for (int k : f.nodes) {
      const auto& x = m.mesh.nodes[k];
      zmin = std::min(zmin, x[2]);
      zmax = std::max(zmax, x[2]);
      rmax = std::max(rmax, std::hypot(x[0], x[1]));
      side = std::max({side, std::abs(x[0]), std::abs(x[1])});
    }
    switch (f.marker) {
      case geo::slide_bottom:
        EXPECT_TRUE(zmax == box.min[2] && zmin == box.min[2]);
        break;
      case geo::slide_sides:  // side faces of each layer: slide, skin (undeformed there), air
        EXPECT_NEAR(side, 6.25, 1e-12);
        EXPECT_TRUE(zmin >= box.min[2] && zmax <= box.min[2] + slide_top);
        break;
      case geo::skin_sides:
        EXPECT_NEAR(side, 6.25, 1e-12);
        EXPECT_TRUE(zmin >= box.min[2] + slide_top && zmax <= box.min[2] + slide_top + skin_top);
        break;
      case geo::air_sides:
        EXPECT_NEAR(side, 6.25, 1e-12);
        EXPECT_TRUE(zmin >= box.min[2] + slide_top + skin_top && zmax <= box.max[2]);
        break;
      case geo::top:
        EXPECT_TRUE(zmin == box.max[2] && rmax >= 1.5 * std::cos(std::numbers::pi / 32) - 1e-9);
        break;
      case geo::pin_top:
        EXPECT_TRUE(zmin == box.max[2] && rmax <= 1.5 + 1e-9);
        break;
      default:
        ADD_FAILURE() << "unexpected marker " << f.marker;
    }
  }
  for (int marker : {geo::slide_bottom, geo::slide_sides, geo::air_sides, geo::top, geo::pin_top})
    EXPECT_GT(count[marker], 0);
  EXPECT_EQ(count[geo::skin_sides] > 0, !spec.baseline);
}

namespace {

/// Volume of the skin tets with their centroid at r < r_max, 0 < z < z_max.
double skin_volume_near_axis(const geo::CompositeMesh& m, double r_max, double z_max) {
  double v = 0;
  for (std::size_t t = 0; t < m.mesh.tets.size(); ++t) {
    if (m.mesh.regions[t] != geo::skin) continue;
    std::array<double, 3> c{0, 0, 0};
    for (const auto n : m.mesh.tets[t])
      for (int k = 0; k < 3; ++k) c[k] += 0.25 * m.mesh.nodes[static_cast<std::size_t>(n)][k];
    if (std::hypot(c[0], c[1]) < r_max && c[2] > 0 && c[2] < z_max) v += mesh::tet_volume(m.mesh, t);
  }
  return v;
}

/// Revolved volume of the N-gon complex of a section polygon (Pappus, N azimuths).
double ngon_volume(const std::vector<geo::ProfilePoint>& p, int n) {
  return revolved_volume(p) * n * std::sin(2 * std::numbers::pi / n) / (2 * std::numbers::pi);
}

}  // namespace

// A compressed zone that reaches the slide around the axis but not on it encloses a lens of
// native skin that no other skin touches: it must be meshed as skin, with its own volume.
TEST(CompositeGeometry, NativeSkinEnclosedByTheCompressedZoneIsSkin) {
  // Synthetic: the lens is the 0.3 x 0.15 mm rectangle at the axis.
  const auto& synthetic = geo::testing::mesh_of(Case::indent_10_native_pocket);
  const double lens =
      ngon_volume({{0, 0}, {0.3, 0}, {0.3, 0.15}, {0, 0.15}}, synthetic.size.azimuth_segments);
  EXPECT_NEAR(skin_volume_near_axis(synthetic, 0.35, 0.15), lens, 1e-6 * lens);
  // The FE profile that first showed it (1.0 mm into 2.0 mm skin): the lens under its
  // outline, from the axis at z = 0.100 to the slide at r = 0.366 mm. Its straight sides
  // survive the outline's simplification (0.05 mm) to well within 5 %.
  const auto& fe = geo::testing::mesh_of(Case::fe_d10_h20);
  const double fe_lens = ngon_volume({{0, 0},
                                      {0.365625, 0},
                                      {0.4523794826, 0.112561732},
                                      {0.379694371, 0.109284287},
                                      {0.3056189525, 0.1063375677},
                                      {0.2303448985, 0.103871483},
                                      {0.1541221219, 0.1020106873},
                                      {0.07723938806, 0.1008321743},
                                      {0, 0.100339883}},
                                     fe.size.azimuth_segments);
  EXPECT_NEAR(skin_volume_near_axis(fe, 0.5, 0.13), fe_lens, 0.05 * fe_lens);
}

INSTANTIATE_TEST_SUITE_P(Geometry, CompositeCase, ::testing::ValuesIn(kAllCases),
                         [](const auto& param_info) { return name_of(param_info.param); });

TEST(CompositeGeometry, DeeperIndentationShrinksTheAir) {
  // The pin goes down with its top face: the air above the skin shrinks with d.
  const auto air = [](Case c) { return stats(geo::testing::mesh_of(c), geo::air)->volume_mm3; };
  EXPECT_GT(air(Case::flat), air(Case::indent_05));
  EXPECT_GT(air(Case::indent_05), air(Case::indent_10));
  EXPECT_GT(air(Case::indent_10), air(Case::indent_15));
  EXPECT_GT(geo::testing::mesh_of(Case::indent_15).contact_radius_mm, 0.9);
}

TEST(CompositeGeometry, SizePresets) {
  const auto fast = geo::resolve_size({});
  const auto paper = geo::resolve_size({"paper", 0, 0});
  EXPECT_DOUBLE_EQ(paper.edge_mm, 0.2);
  EXPECT_LT(paper.max_volume_mm3, fast.max_volume_mm3);
  // One geometry for both presets: only the tets differ.
  EXPECT_EQ(paper.azimuth_segments, fast.azimuth_segments);
  EXPECT_DOUBLE_EQ(paper.section_edge_mm, fast.section_edge_mm);
  const auto explicit_size = geo::resolve_size({"fast", 0.3, 0.01});
  EXPECT_DOUBLE_EQ(explicit_size.edge_mm, 0.3);
  EXPECT_DOUBLE_EQ(explicit_size.max_volume_mm3, 0.01);
  EXPECT_DOUBLE_EQ(geo::resolve_size({"fast", 0.1, 0}).section_edge_mm, 0.1);  // finer refines it
  EXPECT_DOUBLE_EQ(geo::resolve_size({"fast", 0.6, 0}).section_edge_mm, fast.section_edge_mm);
  // The pin's tip is faceted finer than the rest of the section, the same for both presets;
  // an explicit tip segment is honoured but never coarser than the section.
  EXPECT_LT(fast.tip_edge_mm, fast.section_edge_mm);
  EXPECT_DOUBLE_EQ(paper.tip_edge_mm, fast.tip_edge_mm);
  EXPECT_DOUBLE_EQ(geo::resolve_size({"fast", 0, 0, 0.02}).tip_edge_mm, 0.02);
  EXPECT_DOUBLE_EQ(geo::resolve_size({"fast", 0, 0, 0.5}).tip_edge_mm, fast.section_edge_mm);
  // A finer explicit size gives more tets.
  auto spec = geo::testing::spec_of(Case::flat);
  spec.size.max_edge_mm = 0.6;
  spec.size.max_volume_mm3 = 0.3;
  const auto coarse = geo::build_composite(spec);
  spec.size.max_edge_mm = 0.45;
  spec.size.max_volume_mm3 = 0.1;
  const auto fine = geo::build_composite(spec);
  EXPECT_GT(fine.mesh.tets.size(), coarse.mesh.tets.size());
}

TEST(CompositeGeometry, PresetsMeshTheSameGeometry) {
  // The paper preset's section and azimuths with the fast preset's volume bound: the same
  // region volumes (computed from the section) as the fast mesh, to round-off. The tip of
  // the pin is a lens in air whose facets change the transmission by percent.
  auto spec = geo::testing::spec_of(Case::indent_15);
  const auto& fast = geo::testing::mesh_of(Case::indent_15);
  spec.size = {"paper", 0, fast.size.max_volume_mm3};
  const auto paper = geo::build_composite(spec);
  ASSERT_EQ(paper.regions.size(), fast.regions.size());
  for (std::size_t i = 0; i < fast.regions.size(); ++i)
    EXPECT_NEAR(paper.regions[i].expected_volume_mm3, fast.regions[i].expected_volume_mm3,
                1e-9 * fast.regions[i].expected_volume_mm3)
        << "region " << fast.regions[i].region;
  EXPECT_DOUBLE_EQ(paper.contact_radius_mm, fast.contact_radius_mm);
}

// A complex TetGen rejects (here a facet sticking out through the box) gives a
// GeometryError naming the surfaces involved, not a crash. White box: builds the complex by
// hand, since build_composite's own checks stop such input before TetGen.
#include <gtest/gtest.h>

#include "plc.hpp"
#include "tetgen_mesher.hpp"

namespace detail = tocd::sim::geometry::detail;

TEST(GeometryTetgen, RejectedComplexNamesItsSurfaces) {
  detail::Plc plc;
  plc.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},       {0, 1, 0},       {0, 0, 1},       {1, 0, 1},
                {1, 1, 1}, {0, 1, 1}, {0.2, 0.2, 0.5}, {1.5, 0.2, 0.5}, {1.5, 0.8, 0.5}, {0.2, 0.8, 0.5}};
  const int faces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4},
                           {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  for (const auto& f : faces) plc.facets.push_back({{{{f[0], f[1], f[2], f[3]}}}, {}, 0});
  plc.facets.push_back({{{{8, 9, 10, 11}}}, {}, 1});
  plc.seeds.push_back({{0.5, 0.5, 0.25}, 2});
  detail::Section section;
  section.add_surface("the box", 2);
  section.add_surface("the stray sheet", 0);
  try {
    detail::tetrahedralize(plc, section, "pQ");
    FAIL() << "TetGen accepted intersecting facets";
  } catch (const tocd::sim::geometry::GeometryError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("TetGen rejected the composite geometry"), std::string::npos) << m;
    EXPECT_NE(m.find("the stray sheet"), std::string::npos) << m;
    RecordProperty("message", m);
  }
}

// Bad profiles and sizes give a GeometryError naming the surface at fault.
#include <cmath>

#include <gtest/gtest.h>

#include "synthetic_profile.hpp"
#include "tocd/test/error_of.hpp"

namespace geo = tocd::sim::geometry;
using geo::testing::Indentation;

namespace {

std::string error_of(const geo::CompositeSpec& spec) {
  return tocd::test::error_of<geo::GeometryError>([&] { geo::build_composite(spec); });
}

geo::CompositeSpec indented() {
  Indentation in;
  in.spacing_mm = 0.05;
  return geo::testing::make_spec(in);
}

::testing::AssertionResult mentions(const std::string& message, const std::string& what) {
  if (message.find(what) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << message << "' does not mention '" << what << "'";
}

}  // namespace

TEST(GeometryErrors, SkinTopMustStartOnTheAxis) {
  auto spec = indented();
  spec.skin.top_surface.erase(spec.skin.top_surface.begin());
  EXPECT_TRUE(mentions(error_of(spec), "skin top surface: must start on the pin axis"));
}

TEST(GeometryErrors, SkinTopMustBeOrderedOutwards) {
  auto spec = indented();
  std::swap(spec.skin.top_surface[10], spec.skin.top_surface[11]);
  EXPECT_TRUE(mentions(error_of(spec), "skin top surface: not ordered outwards"));
}

TEST(GeometryErrors, SkinTopMustEndOnTheUndeformedTop) {
  auto spec = indented();
  for (auto& p : spec.skin.top_surface) p.z_mm -= 0.5;
  EXPECT_TRUE(mentions(error_of(spec), "skin top surface: ends at"));
}

TEST(GeometryErrors, PinMustNotPenetrateTheSkin) {
  auto spec = indented();
  spec.skin.top_surface.clear();  // flat skin, but the pin is 1 mm down
  spec.skin.compressed_outlines.clear();
  EXPECT_TRUE(mentions(error_of(spec), "skin top surface penetrates the glass pin"));
}

TEST(GeometryErrors, NonFiniteAndSlideTouchingPoints) {
  auto spec = indented();
  spec.skin.top_surface[3].z_mm = std::nan("");
  EXPECT_TRUE(mentions(error_of(spec), "skin top surface: point 3 is not a finite number"));
  spec = indented();
  spec.skin.top_surface[0].z_mm = 0.0;
  EXPECT_TRUE(mentions(error_of(spec), "reaches the slide"));
}

TEST(GeometryErrors, SelfIntersectingOutline) {
  auto spec = indented();
  spec.skin.compressed_outlines = {{{0.1, 0.5}, {0.6, 1.0}, {0.6, 0.5}, {0.1, 1.0}}};
  EXPECT_TRUE(mentions(error_of(spec), "compressed outline 0: self-intersecting"));
}

TEST(GeometryErrors, DegenerateOutline) {
  auto spec = indented();
  spec.skin.compressed_outlines = {{{0.1, 0.5}, {0.3, 0.5}, {0.6, 0.5}}};
  EXPECT_TRUE(mentions(error_of(spec), "compressed outline 0: degenerate"));
  spec.skin.compressed_outlines = {{{0.1, 0.5}, {0.3, 0.5}}};
  EXPECT_TRUE(mentions(error_of(spec), "compressed outline 0: needs at least 3"));
}

TEST(GeometryErrors, OutlineOutsideTheSkin) {
  auto spec = indented();
  spec.skin.compressed_outlines.push_back({{2.0, 2.0}, {3.0, 2.0}, {3.0, 2.9}, {2.0, 2.9}});
  EXPECT_TRUE(mentions(error_of(spec), "compressed outline 1: point"));
  EXPECT_TRUE(mentions(error_of(spec), "lies outside the skin"));
}

TEST(GeometryErrors, OutlineCrossingTheSkinTop) {
  // Both ends just under the curved contact surface; the straight edge between them
  // passes above it, through the pin.
  auto spec = indented();
  const Indentation in;
  const double z0 = geo::testing::surface_height(in, 0.05) - 0.01;
  const double z1 = geo::testing::surface_height(in, 0.9) - 0.01;
  spec.skin.compressed_outlines = {{{0.05, 0.6}, {0.9, 0.6}, {0.9, z1}, {0.05, z0}}};
  const std::string e = error_of(spec);
  EXPECT_TRUE(mentions(e, "compressed outline 0"));
  EXPECT_TRUE(mentions(e, "intersects"));
  EXPECT_TRUE(mentions(e, "pin/skin contact surface"));
}

TEST(GeometryErrors, OverlappingOutlines) {
  auto spec = indented();
  spec.skin.compressed_outlines = {{{2.0, 0.5}, {3.0, 0.5}, {3.0, 1.0}, {2.0, 1.0}},
                                   {{2.5, 0.7}, {3.5, 0.7}, {3.5, 1.2}, {2.5, 1.2}}};
  const std::string e = error_of(spec);
  EXPECT_TRUE(mentions(e, "compressed outline 0"));
  EXPECT_TRUE(mentions(e, "compressed outline 1"));
}

TEST(GeometryErrors, SizesAndPin) {
  auto spec = indented();
  spec.size.preset = "huge";
  EXPECT_TRUE(mentions(error_of(spec), "unknown preset 'huge'"));
  spec = indented();
  spec.size.max_edge_mm = -1;
  EXPECT_TRUE(mentions(error_of(spec), "max_edge_mm must be a positive number"));
  spec = indented();
  spec.size.tip_edge_mm = std::nan("");
  EXPECT_TRUE(mentions(error_of(spec), "tip_edge_mm must be a positive number"));
  spec = indented();
  spec.pin_displacement_mm = 2.5;
  EXPECT_TRUE(mentions(error_of(spec), "glass pin: displacement"));
  spec = indented();
  spec.pin_length_mm = 1.0;
  EXPECT_TRUE(mentions(error_of(spec), "glass pin: length"));
  spec = indented();
  spec.skin_size_mm = 10;
  EXPECT_TRUE(mentions(error_of(spec), "skin_size_mm"));
}

#pragma once

// Composite meshes shared by the tests of one executable: each case is meshed once.

#include <map>
#include <string>

#include "synthetic_profile.hpp"

namespace tocd::sim::geometry::testing {

enum class Case { baseline, flat, indent_05, indent_10, indent_15, indent_15_on_slide };

inline CompositeSpec spec_of(Case c) {
  CompositeSpec spec;
  Indentation in;
  switch (c) {
    case Case::baseline:
      spec.baseline = true;
      return spec;
    case Case::flat:
      return spec;
    case Case::indent_05:
      in.displacement_mm = 0.5;
      break;
    case Case::indent_10:
      in.displacement_mm = 1.0;
      break;
    case Case::indent_15:
      in.displacement_mm = 1.5;
      break;
    case Case::indent_15_on_slide:
      in.displacement_mm = 1.5;
      in.compressed_on_slide = true;
      break;
  }
  return make_spec(in);
}

inline const CompositeMesh& mesh_of(Case c) {
  static std::map<Case, CompositeMesh> cache;
  auto it = cache.find(c);
  if (it == cache.end()) it = cache.emplace(c, build_composite(spec_of(c))).first;
  return it->second;
}

}  // namespace tocd::sim::geometry::testing

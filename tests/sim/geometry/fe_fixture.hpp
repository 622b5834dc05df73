#pragma once

// Skin profiles stored from the FE (tests/sim/geometry/data): "# top surface" then one
// "# compressed outline" section per outline, one "r_mm z_mm" pair per line.

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "tocd/sim/geometry/composite.hpp"

namespace tocd::sim::geometry::testing {

inline SkinProfile load_profile(const std::string& path, double thickness_mm) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  SkinProfile p;
  p.thickness_mm = thickness_mm;
  std::vector<ProfilePoint>* into = nullptr;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("# top surface", 0) == 0) {
      into = &p.top_surface;
    } else if (line.rfind("# compressed outline", 0) == 0) {
      into = &p.compressed_outlines.emplace_back();
    } else if (!line.empty() && line[0] != '#') {
      if (!into) throw std::runtime_error(path + ": data before a section header");
      std::istringstream fields(line);
      ProfilePoint q;
      if (!(fields >> q.r_mm >> q.z_mm)) throw std::runtime_error(path + ": bad line '" + line + "'");
      into->push_back(q);
    }
  }
  return p;
}

}  // namespace tocd::sim::geometry::testing

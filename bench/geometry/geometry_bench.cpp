// Prints, per preset and case, the tets of every region, the volume check and the seconds
// spent building and meshing the composite. Usage: geometry_bench [fast|paper|all]
#include <cstdio>
#include <string>

#include <fmt/format.h>

#include "synthetic_profile.hpp"

namespace geo = tocd::sim::geometry;

int main(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "all";
  struct Case {
    const char* name;
    geo::CompositeSpec spec;
  };
  std::vector<Case> cases;
  geo::CompositeSpec baseline;
  baseline.baseline = true;
  cases.push_back({"baseline", baseline});
  cases.push_back({"flat d=0", geo::CompositeSpec{}});
  for (double d : {0.625, 1.5}) {
    geo::testing::Indentation in;
    in.displacement_mm = d;
    cases.push_back({d == 0.625 ? "d=0.625" : "d=1.5", geo::testing::make_spec(in)});
  }
  fmt::print("{:<6} {:<9} {:>9} {:>8} {:>8} {:>8} {:>8} {:>8} {:>11} {:>7}\n", "preset", "case", "tets",
             "pin", "slide", "air", "skin", "compr", "max |dV|/V", "s");
  for (const std::string preset : {"fast", "paper"}) {
    if (which != "all" && which != preset) continue;
    for (auto& c : cases) {
      c.spec.size.preset = preset;
      const auto m = geo::build_composite(c.spec);
      std::size_t tets[6] = {0, 0, 0, 0, 0, 0};
      double worst = 0;
      for (const auto& r : m.regions) {
        tets[r.region] = r.tets;
        worst = std::max(worst, std::abs(r.volume_mm3 / r.expected_volume_mm3 - 1));
      }
      fmt::print("{:<6} {:<9} {:>9} {:>8} {:>8} {:>8} {:>8} {:>8} {:>11.1e} {:>7.2f}\n", preset, c.name,
                 m.mesh.tets.size(), tets[1], tets[2], tets[3], tets[4], tets[5], worst, m.seconds);
      std::fflush(stdout);
    }
  }
  return 0;
}

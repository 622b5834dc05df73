#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tocd/sim/mc/optics.hpp"
#include "tocd/sim/mesh/tet_mesh.hpp"
#include "tocd/sim/study/study_optics.hpp"

namespace tocd::sim::study {

/// Skin optics from the local water volume fraction w (the biphasic FE's 1 - phi0 / J), in
/// place of the strain threshold (docs/water.md):
///  - refractive index: volume mix of water and dry tissue (Gladstone-Dale law, as used for
///    tissue by Tuchin, "Tissue Optics", 3rd ed., SPIE 2015, ch. 10):
///      n(w) = w n_water + (1 - w) n_dry,   n_water = 1.33, n_dry = 1.53 (dry collagen),
///    so the native index 1.38 of the model note means w_native = (n_dry - 1.38) / 0.2 = 0.75;
///  - clearing fraction f = (n(w) - n_native) / (n_cleared - n_native), clamped to [0, 1]: the
///    way from the native to the published most-cleared state (graded.native / .cleared);
///  - mu_a and mu_s interpolated linearly by f (their published end points), g native.
/// The Monte Carlo holds optics per region, so f is quantised like the strain-graded model
/// (graded.bins levels, region kGradedRegionBase + level; level 0 stays native skin).
struct WaterOptics {
  GradedOptics graded;  ///< end points and bins (graded.full_strain is not used)
  double water_index = 1.33;
  double dry_index = 1.53;
};

/// The Monte Carlo of every time point of a water request, the same for a single ramp + hold
/// (WaterTimeCourseRequest) and a recorded history (WaterHistoryRequest): both requests are one.
struct WaterMcSettings {
  WaterOptics optics;
  std::uint64_t photons = 20000, seed = 1;
  int threads = 0;
  std::string mesh_preset = "fast";
};

/// Water volume fraction of native skin implied by the index mix: (n_dry - n_native) /
/// (n_dry - n_water). Throws tocd::ConfigError when it is not in (0, 1).
double native_water_fraction(const WaterOptics& w);
double mixed_index(double water_fraction, const WaterOptics& w);
double water_clearing_fraction(double water_fraction, const WaterOptics& w);  ///< NaN -> 0
int water_level(double water_fraction, const WaterOptics& w);
/// Optics per region for a mesh split by assign_water_regions (= graded_optics(w.graded)).
mc::Optics water_optics(const WaterOptics& w);
/// Reassigns every skin tet to its water level, evaluating `water_fraction(r, z)` at the tet
/// centroid (deformed configuration, r = sqrt(x^2 + y^2)). Returns tets per level.
std::vector<std::size_t> assign_water_regions(mesh::TetMesh& mesh, const WaterOptics& w,
                                              const std::function<double(double, double)>& water_fraction);

}  // namespace tocd::sim::study

#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/sim/mc/optics.hpp"
#include "tocd/sim/mesh/tet_mesh.hpp"

namespace tocd::sim::study {

/// Optical properties of the model note at 633 nm (mm^-1).
mc::RegionOptics air_optics();
mc::RegionOptics glass_optics();
mc::RegionOptics native_skin_optics();
/// The most cleared state of the published study (simulation 11: mu_a and mu_s at 60 %,
/// n at 110 % of native). Default optics of the compressed region in predictions and the
/// end point of the graded model.
mc::RegionOptics cleared_skin_optics();

/// Optics for the five regions of a composite mesh (pin, slide, air, skin, compressed):
/// glass, glass, air, native skin, and `compressed` for the compressed region.
mc::Optics threshold_optics(const mc::RegionOptics& compressed);

/// Strain-graded skin optics. Each skin tet (native or compressed region) gets the fraction
///   f = clamp(-min_log_strain / full_strain, 0, 1)
/// of the way from `native` to `cleared` (mu_a, mu_s and n interpolated linearly; g from
/// native). The Monte Carlo holds optics per region, so f is quantised to `bins` levels:
/// level k = round(f * bins), k = 0 stays native skin (region 4), k >= 1 becomes region
/// kGradedRegionBase + k with the optics at f = k / bins. With bins = 8 the optics step is
/// 1/8 of the native-to-cleared difference (about 0.004 mm^-1 in mu_a, 1.4 mm^-1 in mu_s).
struct GradedOptics {
  mc::RegionOptics native = native_skin_optics();
  mc::RegionOptics cleared = cleared_skin_optics();
  double full_strain = 0.5;  ///< compressive log strain at which the skin is fully cleared
  int bins = 8;
};
inline constexpr std::int32_t kGradedRegionBase = 100;

/// Level 0..bins for a minimum principal log strain (NaN -> 0). Throws tocd::ConfigError on
/// bins < 1 or full_strain <= 0.
int graded_level(double min_log_strain, const GradedOptics& graded);
/// Optics at fraction f in [0, 1] between native and cleared.
mc::RegionOptics graded_optics_at(double f, const GradedOptics& graded);
/// Optics for a mesh whose skin regions were split by assign_graded_regions.
mc::Optics graded_optics(const GradedOptics& graded);

/// Reassigns every skin tet (regions 4 and 5) of `mesh` to its graded level, evaluating
/// `min_log_strain(r, z)` at the tet centroid (r = sqrt(x^2 + y^2): the FE field is
/// axisymmetric and, like the tet mesh, in the deformed configuration). Returns the number
/// of tets per level (size bins + 1).
std::vector<std::size_t> assign_graded_regions(mesh::TetMesh& mesh, const GradedOptics& graded,
                                               const std::function<double(double, double)>& min_log_strain);

nlohmann::json to_json(const mc::RegionOptics& optics);
mc::RegionOptics region_optics_from_json(const nlohmann::json& j);
nlohmann::json to_json(const GradedOptics& graded);
GradedOptics graded_from_json(const nlohmann::json& j);

}  // namespace tocd::sim::study

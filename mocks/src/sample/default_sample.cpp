#include "tocd/mocks/default_sample.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "tocd/core/error.hpp"

namespace tocd::mocks {

std::vector<double> default_sample_grid(double thickness_mm, double max_displacement_mm) {
  if (!(thickness_mm > 0) || !std::isfinite(thickness_mm))
    throw ConfigError(fmt::format("simulated sample: thickness {} mm must be > 0", thickness_mm));
  const double reach = std::max(max_displacement_mm, kDefaultSampleMinReachMm);
  // Grid points as integer multiples so that 0.25, 0.5, ... are exact and every entry point
  // asks the cache for bit-identical displacements.
  const auto wanted = static_cast<int>(std::ceil(reach / kDefaultSampleGridMm - 1e-9));
  std::vector<double> grid;
  for (int i = 1; i <= wanted; ++i) {
    const double d = i * kDefaultSampleGridMm;
    if (!(d < thickness_mm)) break;  // the pin cannot pass through the sample
    grid.push_back(d);
  }
  if (grid.empty())
    throw ConfigError(fmt::format("simulated sample: {} mm is too thin for the {} mm displacement grid",
                                  thickness_mm, kDefaultSampleGridMm));
  return grid;
}

SimTissueSpec default_sample_spec(double thickness_mm, double max_displacement_mm,
                                  const DefaultSampleOptions& options, const SampleTruth& truth) {
  validate(truth);
  SimTissueSpec spec;
  spec.stiffness_scale = truth.stiffness_scale;
  spec.cleared_mu_a_fraction = truth.cleared_mu_a_fraction;
  spec.cleared_mu_s_fraction = truth.cleared_mu_s_fraction;
  spec.cleared_n_fraction = truth.cleared_n_fraction;
  spec.full_clearing_strain = truth.full_clearing_strain;
  spec.thickness_mm = thickness_mm;
  spec.displacements_mm = default_sample_grid(thickness_mm, max_displacement_mm);
  spec.photons = options.photons;
  spec.threads = options.threads;
  spec.cache_dir = options.cache_dir;
  spec.progress = options.progress;
  return spec;
}

std::shared_ptr<TissueModel> make_default_sample(double thickness_mm, double max_displacement_mm,
                                                 const DefaultSampleOptions& options, SimTissueTable* table) {
  return make_simulated_tissue(default_sample_spec(thickness_mm, max_displacement_mm, options), table);
}

std::shared_ptr<TissueModel> make_default_sample(double thickness_mm, double max_displacement_mm,
                                                 const SampleTruth& truth,
                                                 const DefaultSampleOptions& options, SimTissueTable* table) {
  return make_simulated_tissue(default_sample_spec(thickness_mm, max_displacement_mm, options, truth), table);
}

}  // namespace tocd::mocks

#pragma once

// The simulated lab's default sample: the one every entry point measures (`tocdlab demo`,
// `tocdlab-gui --demo`, `tocdlab simlab`, `tocdlab run --simulated`), so the same protocol
// gives the same measurements wherever it runs. It is the simulator-backed sample of
// sim_tissue.hpp (FE load curve, FE + Monte Carlo transmission) on one fixed displacement grid,
// so all of them share one cache entry per thickness.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tocd/mocks/sample_truth.hpp"
#include "tocd/mocks/sim_tissue.hpp"
#include "tocd/mocks/tissue.hpp"

namespace tocd::mocks {

/// Spacing of the default sample's displacement grid (mm); the demo protocol's steps lie on it.
inline constexpr double kDefaultSampleGridMm = 0.25;
/// The grid reaches at least this far (the demo protocol's deepest step), so protocols that stay
/// within it share the demo's cache entry.
inline constexpr double kDefaultSampleMinReachMm = 1.5;
/// Monte Carlo photons per grid point (the demo's --sample-photons default).
inline constexpr std::uint64_t kDefaultSamplePhotons = 50000;
/// Share of each step's clearing that waits for the water to drain (SimulatedLabOptions; the
/// default SampleTruth's delayed_clearing).
inline constexpr double kDefaultDelayedClearing = SampleTruth{}.delayed_clearing;

/// The displacement grid for a sample `thickness_mm` thick that a protocol drives to
/// `max_displacement_mm`: kDefaultSampleGridMm apart, from one spacing up to the first grid
/// point at or beyond max(max_displacement_mm, kDefaultSampleMinReachMm), kept below the
/// thickness. Throws ConfigError when the sample is too thin for a single grid point.
std::vector<double> default_sample_grid(double thickness_mm, double max_displacement_mm);

/// How the default sample is prepared: photons per grid point, Monte Carlo threads, the cache
/// (default_sim_tissue_cache_dir(); empty: none) and progress lines.
struct DefaultSampleOptions {
  std::uint64_t photons = kDefaultSamplePhotons;
  int threads = 0;
  std::filesystem::path cache_dir;
  std::function<void(const std::string&)> progress;
};

/// The spec of the default sample (sim_tissue.hpp defaults: 1.25 x the published stiffness,
/// graded optics, seed 7) at `thickness_mm` on default_sample_grid(), with the stiffness and
/// clearing of `truth` (validated; ConfigError naming the field). The default truth gives the
/// default sample, bit for bit, and its cache entry.
SimTissueSpec default_sample_spec(double thickness_mm, double max_displacement_mm,
                                  const DefaultSampleOptions& options = {}, const SampleTruth& truth = {});

/// Prepares (or reads from the cache) the default sample; see make_simulated_tissue.
std::shared_ptr<TissueModel> make_default_sample(double thickness_mm, double max_displacement_mm,
                                                 const DefaultSampleOptions& options = {},
                                                 SimTissueTable* table = nullptr);
/// The same with the stiffness and clearing of `truth` (its relaxation and delayed clearing
/// belong to the lab: simulated_lab_options(truth)).
std::shared_ptr<TissueModel> make_default_sample(double thickness_mm, double max_displacement_mm,
                                                 const SampleTruth& truth,
                                                 const DefaultSampleOptions& options = {},
                                                 SimTissueTable* table = nullptr);

}  // namespace tocd::mocks

#pragma once

// A recorded run whose steps carry real predictions (FE + mesh + Monte Carlo through
// SimStepPredictor, few photons), for tests of what is built on stored prediction configs.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace tocd::analysis::testing {

struct PredictedRunSpec {
  std::vector<double> displacements_mm = {0.0, 0.5};
  double thickness_mm = 2.0;
  std::uint64_t photons = 3000;
};

/// Writes the run into a new database at `path` (steps with a load statistic, a prediction per
/// step) and returns its id.
std::int64_t write_predicted_run(const std::filesystem::path& path, const PredictedRunSpec& spec = {});

/// A fit file as `tocdlab fit --method fe --json` writes it (the keys compare --material reads):
/// the published law with every modulus times `factor`, and one confidence law per entry of
/// `band_factors`.
std::string scaled_fit_json(double factor, const std::vector<double>& band_factors);

}  // namespace tocd::analysis::testing

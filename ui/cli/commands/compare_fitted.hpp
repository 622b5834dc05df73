#pragma once

#include <cstdint>
#include <string>

namespace tocd::cli {

/// `tocdlab compare --material fitted|FILE`: every step of a run re-predicted with the sample's
/// own law next to the stored prediction (the default law), with two bands on the fitted T:
/// the Monte Carlo error and the spread over the fit's confidence laws (docs/study.md).
struct CompareFittedOptions {
  std::string db, material;  ///< material: "fitted" (FE fit of the run, `scaled` model) or a fit JSON
  std::int64_t run = 0;
  double pin_radius = 1.5;
  std::uint64_t photons = 0;  ///< 0: the stored configs' photons
  int threads = 0;
  bool json = false;
};

void run_compare_fitted(const CompareFittedOptions& options);

}  // namespace tocd::cli

#pragma once
// A prediction request as the tests of the predictor make them cheap: the pin's depth and the
// Monte Carlo's photons, seed and threads chosen by the test; everything else at the request's
// defaults. Needs tocd_sim_study.
#include <cstdint>

#include "tocd/sim/study/predictor.hpp"

namespace tocd::test {

inline tocd::sim::study::PredictionRequest mc_request(double displacement_mm, std::uint64_t photons,
                                                      std::uint64_t seed, int threads) {
  tocd::sim::study::PredictionRequest r;
  r.displacement_mm = displacement_mm;
  r.photons = photons;
  r.seed = seed;
  r.threads = threads;
  return r;
}

}  // namespace tocd::test

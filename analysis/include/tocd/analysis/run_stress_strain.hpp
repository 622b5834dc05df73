#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "tocd/db/reader.hpp"

namespace tocd::analysis {

/// Nominal stress-strain data of a recorded pin-compression run, in the uniaxial-compression
/// interpretation the published fit used: strain = pin displacement / sample thickness,
/// stress = load / pin cross-section (pi r^2).
struct RunStressStrain {
  std::vector<double> strain;      ///< compression magnitude, ascending
  std::vector<double> stress_MPa;  ///< compression magnitude
  double thickness_mm = 0, pin_radius_mm = 0;
  std::size_t pairs_used = 0;  ///< displacement/load sample pairs on the loading branch
};

/// Pairs the run's displacement and load samples (same poller reading, same timestamp), keeps
/// the loading branch in contact (displacement > 0 and deeper than any reading before it, so
/// holds with their relaxing load and the retraction do not enter), and averages them in `bins`
/// equal strain bins. Throws tocd::Error when the run has no load/displacement channels, no
/// sample thickness, or fewer than `min_points` filled bins.
RunStressStrain stress_strain_from_run(const db::Reader& reader, std::int64_t run_id,
                                       double pin_radius_mm = 1.5, std::size_t bins = 40,
                                       std::size_t min_points = 8);

}  // namespace tocd::analysis

#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tocd::cli {

/// `tocdlab fit --method fe`: the Ogden law identified with the pin-compression FE in the
/// loop, optionally jointly with closed-form datasets (docs/fe.md, "Inverse FE fit").
struct FitFeOptions {
  std::string csv, db, model = "ogden3";
  std::int64_t run = 0;
  double pin_radius = 1.5, thickness = 0, poisson = 0.49, weight = 1, refine = 1, confidence = 0.95;
  std::size_t bins = 16;
  std::string kinematics = "axi", bottom = "bonded";
  std::string points = "held";  ///< a run's loads: held | loading (analysis::RunLoadPoints)
  bool fit_D = false, json = false;
  /// Extra datasets "MODE:FILE[:WEIGHT]", MODE uniaxial | equibiaxial | simple-shear | pin.
  std::vector<std::string> datasets;
};

void run_fit_fe(const FitFeOptions& options);

}  // namespace tocd::cli

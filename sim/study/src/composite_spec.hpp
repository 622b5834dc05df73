// The composite mesh a prediction request asks for: shared by the predictor (which meshes it)
// and validate() (which refuses one too large to mesh before any work).
#pragma once

#include "tocd/sim/geometry/composite.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace tocd::sim::study {

/// The composite spec of request `r` with the skin's top `profile`.
geometry::CompositeSpec composite_spec(const PredictionRequest& r, const geometry::SkinProfile& profile);

}  // namespace tocd::sim::study

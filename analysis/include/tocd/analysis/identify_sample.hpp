#pragma once

// What a recorded run says about its sample: the mechanics (identify_mechanics.hpp) and the
// clearing (identify_clearing.hpp, identify_optics.hpp), each with intervals, correlations and
// the parameters the run does not determine.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "tocd/analysis/identify_clearing.hpp"
#include "tocd/analysis/identify_mechanics.hpp"
#include "tocd/analysis/identify_optics.hpp"
#include "tocd/db/reader.hpp"

namespace tocd::analysis {

struct SampleIdentificationOptions {
  MechanicsOptions mechanics;
  bool clearing = true;       ///< the clearing's time course (no Monte Carlo; seconds)
  bool optics = true;         ///< the optics' Monte Carlo (minutes), after the clearing
  OpticsOptions monte_carlo;  ///< the optics' Monte Carlo (photons, seed, threads)
  std::function<void(const std::string&)> progress;
};

struct SampleIdentification {
  std::int64_t run_id = 0;
  double thickness_mm = 0;
  MechanicsIdentification mechanics;
  std::optional<ClearingIdentification> clearing;  ///< when the run recorded transmission
  std::optional<OpticsIdentification> optics;      ///< with the clearing, unless asked not to
  /// Why the optics were not identified although asked for (too few held displacements), or
  /// empty. The mechanics and the clearing stand without them.
  std::string optics_not_identified;
  double seconds = 0;
};

/// Identifies the sample of run `run_id`. Throws tocd::Error naming what the run lacks.
SampleIdentification identify_sample(const db::Reader& reader, std::int64_t run_id,
                                     const SampleIdentificationOptions& options = {});

nlohmann::json to_json(const SampleIdentification& id);

}  // namespace tocd::analysis

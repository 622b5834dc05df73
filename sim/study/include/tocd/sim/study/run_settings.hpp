#pragma once

namespace tocd::sim::study {

/// Hands on the Monte Carlo run settings (photons, seed, mesh preset, threads) from an options
/// record to the request it makes. PredictionRequest, WaterHistoryRequest and the option
/// records that build them name these four alike and mean the same by them.
template <class Request, class Settings>
void copy_run_settings(Request& to, const Settings& from) {
  to.photons = from.photons;
  to.seed = from.seed;
  to.mesh_preset = from.mesh_preset;
  to.threads = from.threads;
}

}  // namespace tocd::sim::study

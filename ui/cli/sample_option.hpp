#pragma once

// The simulated lab's sample as the commands that start one offer it: `--sample simulated`
// (the default: the FE + Monte Carlo backed sample every entry point measures,
// tocd/mocks/default_sample.hpp) or `--sample analytic` (the closed-form stand-in: ready at
// once, for quick trials of the instruments and the run engine).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "tocd/acquisition/protocol.hpp"
#include "tocd/mocks/default_sample.hpp"
#include "tocd/mocks/sim_tissue.hpp"
#include "tocd/mocks/tissue.hpp"

namespace tocd::cli {

struct SampleChoice {
  std::string kind = "simulated";   ///< "simulated" | "analytic"
  std::filesystem::path cache_dir;  ///< the sample cache (default_sim_tissue_cache_dir())
  bool no_cache = false;
  std::uint64_t photons = mocks::kDefaultSamplePhotons;  ///< per grid point
  int threads = 0;                                       ///< Monte Carlo threads (0 = all cores)
};

/// Adds --sample, --cache-dir and --no-cache to `cmd`.
void add_sample_options(CLI::App& cmd, SampleChoice& choice);

/// The chosen sample, `thickness_mm` thick, for steps down to `max_displacement_mm`; the
/// simulated one is prepared (or read from the cache) with its stages as a progress bar on
/// stderr; `table` (when given) receives its tables, time and cache entry.
std::shared_ptr<mocks::TissueModel> prepare_sample(const SampleChoice& choice, double thickness_mm,
                                                   double max_displacement_mm,
                                                   mocks::SimTissueTable* table = nullptr);
/// The same for a protocol: its sample's thickness, down to its deepest step.
std::shared_ptr<mocks::TissueModel> prepare_sample(const SampleChoice& choice,
                                                   const acquisition::Protocol& protocol,
                                                   mocks::SimTissueTable* table = nullptr);

}  // namespace tocd::cli

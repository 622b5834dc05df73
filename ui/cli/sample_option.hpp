#pragma once

// The simulated lab's sample as the commands that start one offer it: `--sample simulated`
// (the default: the FE + Monte Carlo backed sample every entry point measures,
// tocd/mocks/default_sample.hpp) or `--sample analytic` (the closed-form stand-in: ready at
// once, for quick trials of the instruments and the run engine), and the sample's truth
// (--truth-*: its stiffness, relaxation and clearing; tocd/mocks/sample_truth.hpp).

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "tocd/acquisition/protocol.hpp"
#include "tocd/mocks/default_sample.hpp"
#include "tocd/mocks/sample_truth.hpp"
#include "tocd/mocks/sim_tissue.hpp"
#include "tocd/mocks/simulated_lab.hpp"
#include "tocd/mocks/tissue.hpp"

namespace tocd::cli {

struct SampleChoice {
  std::string kind = "simulated";   ///< "simulated" | "analytic"
  std::filesystem::path cache_dir;  ///< the sample cache (default_sim_tissue_cache_dir())
  bool no_cache = false;
  std::uint64_t photons = mocks::kDefaultSamplePhotons;  ///< per grid point
  int threads = 0;                                       ///< Monte Carlo threads (0 = all cores)
  /// --truth-* as given, one per field of mocks::kSampleTruthFields (same order).
  std::array<std::optional<double>, std::size(mocks::kSampleTruthFields)> truth;
  std::optional<std::uint64_t> truth_seed;  ///< --truth-seed: draw the fields not given
};

/// Adds --sample, --cache-dir, --no-cache and the truth options to `cmd`.
void add_sample_options(CLI::App& cmd, SampleChoice& choice);
/// Adds the truth options alone: --truth-seed and one --truth-* per field (the options of
/// mocks::kSampleTruthFields), each checked
/// against mocks::sample_truth_limits() (a value outside is a usage error naming the option).
/// With `delayed_clearing_alias`, --delayed-clearing is another name of --truth-delayed-clearing.
void add_truth_options(CLI::App& cmd, SampleChoice& choice, bool delayed_clearing_alias = false);
/// Whether any truth option was given.
bool truth_given(const SampleChoice& choice);
/// The first truth option given (--truth-seed first, then in field order), or nullptr.
const char* first_truth_option(const SampleChoice& choice);
/// The sample's truth: drawn from the documented ranges with --truth-seed (else the default
/// sample's), each field given on the command line over it. The analytic sample has no FE
/// stiffness nor graded optics: with --sample analytic, --truth-seed and the stiffness and
/// clearing options are refused (CLI::ValidationError naming the option: a usage error);
/// relaxation and delayed clearing belong to the lab and apply to both samples.
mocks::SampleTruth sample_truth(const SampleChoice& choice);
/// Lab options with the truth's relaxation and delayed clearing (mocks::simulated_lab_options);
/// the analytic sample clears at once unless --truth-delayed-clearing says otherwise.
mocks::SimulatedLabOptions simulated_lab_options(const SampleChoice& choice);

/// The chosen sample, `thickness_mm` thick, for steps down to `max_displacement_mm`, with the
/// stiffness and clearing of sample_truth(choice); the simulated one is prepared (or read from the cache)
/// with its stages as a progress bar on stderr; `table` (when given) receives its tables, time and cache
/// entry.
std::shared_ptr<mocks::TissueModel> prepare_sample(const SampleChoice& choice, double thickness_mm,
                                                   double max_displacement_mm,
                                                   mocks::SimTissueTable* table = nullptr);
/// The same for a protocol: its sample's thickness, down to its deepest step.
std::shared_ptr<mocks::TissueModel> prepare_sample(const SampleChoice& choice,
                                                   const acquisition::Protocol& protocol,
                                                   mocks::SimTissueTable* table = nullptr);

}  // namespace tocd::cli

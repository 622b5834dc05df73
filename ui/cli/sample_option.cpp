#include "sample_option.hpp"

#include <algorithm>
#include <cstdint>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "numeric_options.hpp"
#include "progress.hpp"
#include "tocd/core/error.hpp"
#include "tocd/mocks/default_sample.hpp"
#include "tocd/mocks/sim_tissue_cache.hpp"

namespace tocd::cli {

void add_sample_options(CLI::App& cmd, SampleChoice& choice) {
  choice.cache_dir = mocks::default_sim_tissue_cache_dir();
  cmd.add_option("--sample", choice.kind,
                 "the simulated lab's sample: simulated (FE + Monte Carlo backed, the one `tocdlab demo` "
                 "measures; prepared once, then cached) or analytic (closed-form stand-in, ready at once)")
      ->check(CLI::IsMember({"simulated", "analytic"}))
      ->capture_default_str();
  cmd.add_option("--cache-dir", choice.cache_dir,
                 "where the simulated sample's prepared tables are cached ($TOCDLAB_CACHE_DIR, else "
                 "$XDG_CACHE_HOME/tocdlab, else ~/.cache/tocdlab)")
      ->capture_default_str();
  cmd.add_flag("--no-cache", choice.no_cache, "prepare the simulated sample afresh and do not cache it");
  add_truth_options(cmd, choice);
}

namespace {

// What each field means, for --help (kSampleTruthFields order).
constexpr const char* kTruthHelp[] = {
    "the simulated sample's stiffness: shear moduli of the published Ogden skin law times this",
    "the sample's overstress: share of each increment of equilibrium load carried while the water "
    "has not drained (standard linear solid)",
    "decay time of that overstress while the pin holds (s)",
    "fully cleared mu_a / native",
    "fully cleared mu_s / native",
    "fully cleared n / native (native n 1.38)",
    "compressive log strain at which the skin is fully cleared",
    "share of each change of transmission that waits for the water to drain; 0: the sample clears at "
    "once",
    "time constant of that delayed clearing (s; the drained displacement's)"};
static_assert(std::size(kTruthHelp) == std::size(mocks::kSampleTruthFields));

// The fields that only the FE + Monte Carlo sample has (stiffness and clearing).
bool simulated_only(std::size_t field) {
  const std::string name = mocks::kSampleTruthFields[field].name;
  return name != "relaxation_fraction" && name != "relaxation_time_s" && name != "delayed_clearing" &&
         name != "delayed_clearing_time_s";
}

std::size_t field_index(const std::string& name) {
  for (std::size_t i = 0; i < std::size(mocks::kSampleTruthFields); ++i)
    if (name == mocks::kSampleTruthFields[i].name) return i;
  throw std::logic_error("no sample truth field " + name);
}

}  // namespace

void add_truth_options(CLI::App& cmd, SampleChoice& choice, bool delayed_clearing_alias) {
  const mocks::SampleTruth defaults;
  const mocks::SampleTruthRanges limits = mocks::sample_truth_limits();
  const mocks::SampleTruthRanges drawn;
  const bool has_sample_choice = cmd.get_option_no_throw("--sample") != nullptr;
  cmd.add_option(mocks::kSampleTruthSeedOption, choice.truth_seed,
                 "draw the simulated sample's truth (every --truth-* not given) uniformly from its "
                 "documented ranges with this seed")
      ->check(whole_in(std::uint64_t{0}, std::numeric_limits<std::uint64_t>::max()));
  for (std::size_t i = 0; i < std::size(mocks::kSampleTruthFields); ++i) {
    const auto& f = mocks::kSampleTruthFields[i];
    std::string names = mocks::kSampleTruthFields[i].option;
    if (delayed_clearing_alias && std::string(f.name) == "delayed_clearing") names += ",--delayed-clearing";
    const mocks::TruthRange& lim = limits.*f.range;
    const mocks::TruthRange& r = drawn.*f.range;
    cmd.add_option(names, choice.truth[i],
                   fmt::format("{} (default {}; --truth-seed draws it from {} to {}{})", kTruthHelp[i],
                               defaults.*f.value, r.lo, r.hi,
                               has_sample_choice && simulated_only(i) ? "; not with --sample analytic" : ""))
        ->check(real_in(lim.lo, lim.hi));
  }
}

const char* first_truth_option(const SampleChoice& choice) {
  if (choice.truth_seed) return mocks::kSampleTruthSeedOption;
  for (std::size_t i = 0; i < choice.truth.size(); ++i)
    if (choice.truth[i]) return mocks::kSampleTruthFields[i].option;
  return nullptr;
}

bool truth_given(const SampleChoice& choice) {
  return first_truth_option(choice) != nullptr;
}

mocks::SampleTruth sample_truth(const SampleChoice& choice) {
  if (choice.kind == "analytic") {
    if (choice.truth_seed)
      throw CLI::ValidationError(mocks::kSampleTruthSeedOption,
                                 "draws a stiffness and clearing the analytic sample does not have; use "
                                 "--sample simulated");
    for (std::size_t i = 0; i < choice.truth.size(); ++i)
      if (choice.truth[i] && simulated_only(i))
        throw CLI::ValidationError(mocks::kSampleTruthFields[i].option,
                                   "the analytic sample has no FE stiffness nor graded optics; use "
                                   "--sample simulated");
  }
  mocks::SampleTruth t =
      choice.truth_seed ? mocks::draw_sample_truth(*choice.truth_seed) : mocks::SampleTruth{};
  for (std::size_t i = 0; i < choice.truth.size(); ++i)
    if (choice.truth[i]) t.*mocks::kSampleTruthFields[i].value = *choice.truth[i];
  try {
    mocks::validate(t);
  } catch (const ConfigError& e) {  // each option is checked on its own: not expected
    throw CLI::ValidationError("--truth-*", e.what());
  }
  return t;
}

mocks::SimulatedLabOptions simulated_lab_options(const SampleChoice& choice) {
  const mocks::SampleTruth t = sample_truth(choice);
  mocks::SimulatedLabOptions o = mocks::simulated_lab_options(t);
  if (choice.kind == "analytic" && !choice.truth[field_index("delayed_clearing")]) o.delayed_clearing = 0.0;
  return o;
}

std::shared_ptr<mocks::TissueModel> prepare_sample(const SampleChoice& choice, double thickness_mm,
                                                   double max_displacement_mm,
                                                   mocks::SimTissueTable* table_out) {
  const mocks::SampleTruth truth = sample_truth(choice);
  if (choice.kind == "analytic") return mocks::make_analytic_tissue(thickness_mm);
  mocks::DefaultSampleOptions so;
  so.photons = choice.photons;
  so.threads = choice.threads;
  if (!choice.no_cache) so.cache_dir = choice.cache_dir;
  // Stages of the preparation as notes above a bar over them (FE, then one Monte Carlo point
  // per tabulated displacement plus the glass-only baseline). A note that is no stage (a cache
  // entry that could not be written) must not push the count past the total.
  const std::uint64_t total = mocks::default_sample_grid(thickness_mm, max_displacement_mm).size() + 3;
  mocks::SimTissueTable table;
  std::shared_ptr<mocks::TissueModel> tissue;
  {
    ProgressBar bar("simulated sample", total, "stages");
    std::uint64_t stages = 0;
    so.progress = [&](const std::string& line) {
      bar.note(line);
      bar.update(std::min(++stages, total));
    };
    tissue = mocks::make_default_sample(thickness_mm, max_displacement_mm, truth, so, &table);
  }
  if (!progress_quiet())
    std::cerr << fmt::format("simulated sample ready ({:.1f} s{})\n", table.seconds,
                             table.from_cache ? ", from cache" : "");
  if (table_out) *table_out = std::move(table);
  return tissue;
}

std::shared_ptr<mocks::TissueModel> prepare_sample(const SampleChoice& choice,
                                                   const acquisition::Protocol& protocol,
                                                   mocks::SimTissueTable* table) {
  double deepest = 0;
  for (const auto& s : protocol.steps) deepest = std::max(deepest, s.displacement_mm);
  return prepare_sample(choice, protocol.sample.thickness_mm, deepest, table);
}

}  // namespace tocd::cli

#include "sample_option.hpp"

#include <algorithm>
#include <cstdint>
#include <iostream>
#include <utility>

#include <fmt/format.h>

#include "progress.hpp"
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
}

std::shared_ptr<mocks::TissueModel> prepare_sample(const SampleChoice& choice, double thickness_mm,
                                                   double max_displacement_mm,
                                                   mocks::SimTissueTable* table_out) {
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
    tissue = mocks::make_default_sample(thickness_mm, max_displacement_mm, so, &table);
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

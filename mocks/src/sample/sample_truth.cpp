#include "tocd/mocks/sample_truth.hpp"

#include <cmath>
#include <random>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tocd/core/error.hpp"

namespace tocd::mocks {

SampleTruthRanges sample_truth_limits() {
  SampleTruthRanges l;
  l.stiffness_scale = {0.2, 5.0};
  l.relaxation_fraction = {0.0, 2.0};
  l.relaxation_time_s = {0.1, 3600.0};
  l.cleared_mu_a_fraction = {0.05, 1.0};
  l.cleared_mu_s_fraction = {0.05, 1.0};
  l.cleared_n_fraction = {1.0, 1.13};
  l.full_clearing_strain = {0.05, 1.5};
  l.delayed_clearing = {0.0, 1.0};
  l.delayed_clearing_time_s = {0.1, 3600.0};
  return l;
}

namespace {

bool inside(double v, const TruthRange& r) {
  return std::isfinite(v) && v >= r.lo && v <= r.hi;
}

}  // namespace

void validate(const SampleTruth& truth) {
  const SampleTruthRanges limits = sample_truth_limits();
  for (const auto& f : kSampleTruthFields) {
    const double v = truth.*f.value;
    const TruthRange& r = limits.*f.range;
    if (!inside(v, r))
      throw ConfigError(fmt::format("sample truth: {} = {} is outside {} to {}", f.name, v, r.lo, r.hi));
  }
}

SampleTruth draw_sample_truth(std::uint64_t seed, const SampleTruthRanges& ranges) {
  const SampleTruthRanges limits = sample_truth_limits();
  // std::uniform_real_distribution differs between standard libraries: 53 bits by hand.
  std::mt19937_64 rng(seed);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  SampleTruth t;
  for (const auto& f : kSampleTruthFields) {
    const TruthRange& r = ranges.*f.range;
    const TruthRange& l = limits.*f.range;
    if (!(r.lo <= r.hi) || !inside(r.lo, l) || !inside(r.hi, l))
      throw ConfigError(fmt::format("sample truth ranges: {} {} to {} must be an interval within {} to {}",
                                    f.name, r.lo, r.hi, l.lo, l.hi));
    t.*f.value = r.lo + (r.hi - r.lo) * uniform();
  }
  return t;
}

nlohmann::json to_json(const SampleTruth& truth) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& f : kSampleTruthFields) j[f.name] = truth.*f.value;
  return j;
}

}  // namespace tocd::mocks

#pragma once

// The simulated sample's truth: every number the simulated lab's sample is made of (its
// stiffness, its relaxation, how far and how fast it clears). The default is the sample every
// entry point measures (default_sample.hpp); a calibration sets or draws other truths and
// checks that identification recovers them. Nothing that identifies a sample reads this.

#include <cstdint>

#include <nlohmann/json_fwd.hpp>

namespace tocd::mocks {

struct SampleTruth {
  double stiffness_scale = 1.25;       // shear moduli of the published Ogden law times this (D / it)
  double relaxation_fraction = 0.3;    // overstress per increment of equilibrium load (standard linear solid)
  double relaxation_time_s = 20.0;     // its decay time while holding
  double cleared_mu_a_fraction = 0.6;  // fully cleared mu_a / native
  double cleared_mu_s_fraction = 0.6;  // fully cleared mu_s / native
  double cleared_n_fraction = 1.1;     // fully cleared n / native
  double full_clearing_strain = 0.5;   // compressive log strain of full clearing
  double delayed_clearing = 0.3;       // share of each change of T that waits for the water to drain
  double delayed_clearing_time_s = 20.0;  // its time constant (the drained displacement's)

  bool operator==(const SampleTruth&) const = default;
};

/// A closed interval [lo, hi].
struct TruthRange {
  double lo = 0, hi = 0;
};

/// Ranges a calibration draws truths from (draw_sample_truth: uniform in each, independently).
/// Each lies around the default sample and inside the limits validate() accepts:
/// - stiffness_scale 0.6..2.0: half to twice the default sample's 1.25 x the published law,
///   about the spread of skin stiffness between donors and sites.
/// - relaxation_fraction 0.1..0.5 and relaxation_time_s 8..40 s: the overstress share and decay
///   time of a standard linear solid fitted to skin relaxing under a held indentation.
/// - cleared_mu_a_fraction, cleared_mu_s_fraction 0.4..0.9: mild to strong compression clearing
///   around the published 0.6.
/// - cleared_n_fraction 1.02..1.12: n of fully cleared skin 1.408..1.546. The bound is not the
///   glass (n 1.458): the published cleared state already lies above it (1.1 x 1.38 = 1.518),
///   and the Monte Carlo refracts and reflects (Fresnel, total internal reflection) at any
///   index step, so skin denser than glass is fine. The physical bound is the dry collagen the
///   compressed skin tends to, n about 1.55: 1.12 x 1.38 = 1.546 stays below it.
/// - full_clearing_strain 0.3..0.7: compressive log strain at which clearing is complete
///   (the published threshold model clears at 0.5).
/// - delayed_clearing 0..0.5 and delayed_clearing_time_s 8..40 s: from instant clearing to half
///   of it waiting for the water, draining about as fast as the load relaxes.
struct SampleTruthRanges {
  TruthRange stiffness_scale{0.6, 2.0};
  TruthRange relaxation_fraction{0.1, 0.5};
  TruthRange relaxation_time_s{8.0, 40.0};
  TruthRange cleared_mu_a_fraction{0.4, 0.9};
  TruthRange cleared_mu_s_fraction{0.4, 0.9};
  TruthRange cleared_n_fraction{1.02, 1.12};
  TruthRange full_clearing_strain{0.3, 0.7};
  TruthRange delayed_clearing{0.0, 0.5};
  TruthRange delayed_clearing_time_s{8.0, 40.0};
};

/// What validate() accepts (inclusive): wider than the drawing ranges, still physical and
/// within what the FE and the Monte Carlo handle. Clearing lowers mu_a and mu_s (fractions up
/// to 1: no change) and raises n (1 to 1.13: at most n 1.56, dry collagen); a share of delayed
/// clearing is at most the whole change.
SampleTruthRanges sample_truth_limits();

/// A truth drawn uniformly and independently from `ranges`, field by field in declaration
/// order, from a 64-bit Mersenne twister seeded with `seed`: the same seed gives the same
/// truth on every platform. Throws tocd::ConfigError when a range is empty (lo > hi) or reaches
/// outside sample_truth_limits() (naming the field).
SampleTruth draw_sample_truth(std::uint64_t seed, const SampleTruthRanges& ranges = {});

/// Throws tocd::ConfigError naming the first field outside sample_truth_limits() (or not
/// finite) and its allowed range, e.g. "sample truth: stiffness_scale = 9 is outside 0.2 to 5".
void validate(const SampleTruth& truth);

/// The truth as a JSON object, one key per field (the field names above).
nlohmann::json to_json(const SampleTruth& truth);

/// Every field by name, in declaration order (for option tables, JSON and messages), with the
/// command-line option that sets it in `tocdlab` (demo, simlab, run --simulated) and
/// `tocdlab-gui --demo`.
struct SampleTruthField {
  const char* name;
  const char* option;
  double SampleTruth::*value;
  TruthRange SampleTruthRanges::*range;
};
inline constexpr SampleTruthField kSampleTruthFields[] = {
    {"stiffness_scale", "--truth-stiffness-scale", &SampleTruth::stiffness_scale,
     &SampleTruthRanges::stiffness_scale},
    {"relaxation_fraction", "--truth-relaxation-fraction", &SampleTruth::relaxation_fraction,
     &SampleTruthRanges::relaxation_fraction},
    {"relaxation_time_s", "--truth-relaxation-time", &SampleTruth::relaxation_time_s,
     &SampleTruthRanges::relaxation_time_s},
    {"cleared_mu_a_fraction", "--truth-cleared-mu-a", &SampleTruth::cleared_mu_a_fraction,
     &SampleTruthRanges::cleared_mu_a_fraction},
    {"cleared_mu_s_fraction", "--truth-cleared-mu-s", &SampleTruth::cleared_mu_s_fraction,
     &SampleTruthRanges::cleared_mu_s_fraction},
    {"cleared_n_fraction", "--truth-cleared-n", &SampleTruth::cleared_n_fraction,
     &SampleTruthRanges::cleared_n_fraction},
    {"full_clearing_strain", "--truth-full-clearing-strain", &SampleTruth::full_clearing_strain,
     &SampleTruthRanges::full_clearing_strain},
    {"delayed_clearing", "--truth-delayed-clearing", &SampleTruth::delayed_clearing,
     &SampleTruthRanges::delayed_clearing},
    {"delayed_clearing_time_s", "--truth-delayed-clearing-time", &SampleTruth::delayed_clearing_time_s,
     &SampleTruthRanges::delayed_clearing_time_s},
};
/// The option that draws every field not given (draw_sample_truth with the default ranges).
inline constexpr const char* kSampleTruthSeedOption = "--truth-seed";

}  // namespace tocd::mocks

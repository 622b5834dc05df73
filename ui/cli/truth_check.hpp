#pragma once

// The demo's identified sample held against the simulated sample's truth. Only the demo knows
// that truth (the identification never reads it, tocd/mocks/sample_truth.hpp); this is where it
// says how close the identification came:
// - each identified parameter that has a truth: is it inside its 95 % interval?
// - each step: the T re-predicted with the identified sample beside the measured T, in units
//   of their combined standard error.
//
// The combined standard error has three parts. The measured window mean's own scatter and the
// re-prediction's Monte Carlo error are the two a lab would have. The third is the simulated
// sample's: its transmission is itself a Monte Carlo table (its photons, its seed), so even the
// model at the true parameters differs from it by that table's error. Left out, the comparison
// would blame the identification for the sample's own noise (at the default 50,000 photons
// per point it is 0.6-1.2 % of T, as large as the re-prediction's).

#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/analysis/identify_sample.hpp"
#include "tocd/mocks/sample_truth.hpp"
#include "tocd/mocks/sim_tissue.hpp"

namespace tocd::cli {

struct TruthCheck {
  struct Parameter {
    std::string name;  ///< as the identification names it (g1, tau1_s, ...)
    double truth = 0, value = 0, lo = 0, hi = 0;
    bool determined = false;
    bool covered = false;  ///< lo <= truth <= hi (reported for determined parameters only)
  };
  struct Step {
    int step = 0;  ///< 1-based, as in the tables
    double displacement_mm = 0;
    double measured_T = 0, measured_se = 0;  ///< the recording window's mean and its scatter
    double sample_se = 0;                    ///< the simulated sample's own Monte Carlo error
    double predicted_T = 0, predicted_se = 0;
    double combined_se = 0;  ///< the three above in quadrature
    double z = 0;            ///< (predicted - measured) / combined_se
  };
  std::vector<Parameter> parameters;
  std::vector<Step> steps;  ///< empty when the optics were not identified

  int determined() const;
  int covered() const;                      ///< determined and covered
  int steps_within(double multiple) const;  ///< |z| <= multiple
};

/// The check of `id` against the simulated sample built with `truth` and tabulated as `table`
/// (its transmission and the transmission's standard error per displacement). Identified
/// parameters without a truth (the load offset, the equilibrium T per step) are left out, and
/// so are g1 and tau1_s when the mechanics has more than one Prony term (the sample relaxes
/// with one). The sample's error at a step is its table's relative error, linear in the
/// displacement between the table's points, times the measured T.
TruthCheck check_against_truth(const analysis::SampleIdentification& id, const mocks::SampleTruth& truth,
                               const mocks::SimTissueTable& table);

void print_truth_check(std::ostream& out, const TruthCheck& check);
nlohmann::json to_json(const TruthCheck& check);

}  // namespace tocd::cli

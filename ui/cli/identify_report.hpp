#pragma once

// The identified sample as a lab user reads it (tocdlab identify, and below the demo's table).

#include <ostream>
#include <string>

#include "tocd/analysis/identify_sample.hpp"

namespace tocd::cli {

/// A 95 % interval as the reports print it: "[lo, hi]" to five digits, or "none" when an end
/// is not finite.
std::string interval_text(double lo, double hi);

void print_identification(std::ostream& out, const analysis::SampleIdentification& id);

}  // namespace tocd::cli

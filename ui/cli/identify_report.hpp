#pragma once

// The identified sample as a lab user reads it (tocdlab identify, and below the demo's table).

#include <ostream>

#include "tocd/analysis/identify_sample.hpp"

namespace tocd::cli {

void print_identification(std::ostream& out, const analysis::SampleIdentification& id);

}  // namespace tocd::cli

#pragma once

#include <vector>

namespace tocd::acquisition {

/// Nominal compressive strain of a pin step: displacement / sample thickness (both mm).
double nominal_strain(double displacement_mm, double thickness_mm);

/// `count` equally spaced pin displacements from `first_mm` to `last_mm` inclusive (mm).
std::vector<double> linear_steps(double first_mm, double last_mm, int count);

}  // namespace tocd::acquisition

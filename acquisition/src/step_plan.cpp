#include "tocd/acquisition/step_plan.hpp"

#include <string>

#include "tocd/core/error.hpp"

namespace tocd::acquisition {

double nominal_strain(double displacement_mm, double thickness_mm) {
  if (!(thickness_mm > 0.0)) {
    throw ConfigError("sample thickness must be positive, got " + std::to_string(thickness_mm) + " mm");
  }
  return displacement_mm / thickness_mm;
}

std::vector<double> linear_steps(double first_mm, double last_mm, int count) {
  if (count < 1) throw ConfigError("a protocol needs at least one step, got " + std::to_string(count));
  if (count == 1) return {first_mm};
  std::vector<double> steps(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    steps[static_cast<std::size_t>(i)] = first_mm + (last_mm - first_mm) * i / (count - 1);
  }
  return steps;
}

}  // namespace tocd::acquisition

// Prints the cost of the default FE solves: the published 2.5 mm case to 1.5 mm and a 1.5 mm
// skin to 1.2 mm (the thin-skin experiments), both axisymmetric and bonded; then the published
// case straight to 1.5 mm axisymmetric and as a plane-stress section (the published model's
// choice), with the ratio of their CPU times.
#include <chrono>
#include <ctime>

#include <fmt/format.h>

#include "tocd/sim/fe/solve.hpp"

namespace fe = tocd::sim::fe;

namespace {
/// Solves, prints and returns the CPU seconds.
double run(const char* name, const fe::FeModel& m, const std::vector<double>& d) {
  const std::clock_t c0 = std::clock();
  const fe::FeResult r = fe::solve(m, d);
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  fmt::print("{}: {} elements, {:.2f} s wall, {:.2f} s CPU, {} load increments, {} Newton iterations{}\n",
             name, r.steps.empty() ? 0 : r.steps.back().mesh.quads.size(), r.seconds, cpu,
             r.total_load_increments, r.total_newton_iterations,
             r.complete ? "" : " INCOMPLETE: " + r.stop_reason);
  for (const auto& s : r.steps)
    fmt::print("  d = {:.3f} mm  F = {:.5f} N  compressed area {:.4f} mm2  volume {:.4f} mm3\n",
               s.displacement_mm, s.force_N, s.compressed_area_mm2, s.compressed_volume_mm3);
  return cpu;
}
}  // namespace

int main() {
  run("published 2.5 mm skin to 1.5 mm", fe::FeModel::published_default(), {0.625, 1.25, 1.5});
  fe::FeModel thin = fe::FeModel::published_default();
  thin.thickness_mm = 1.5;
  run("1.5 mm skin to 1.2 mm", thin, {0.3, 0.6, 0.9, 1.2});
  const double axi =
      run("published case straight to 1.5 mm, axisymmetric", fe::FeModel::published_default(), {1.5});
  fe::FeModel section = fe::FeModel::published_default();
  section.kinematics = fe::Kinematics::plane_stress;
  const double plane_stress = run("published case straight to 1.5 mm, plane stress", section, {1.5});
  fmt::print("plane stress / axisymmetric CPU time: {:.2f}\n", plane_stress / axi);
  return 0;
}

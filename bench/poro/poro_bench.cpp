// Prints the cost of one hold's time course with the request defaults (pin to 1.25 mm in 30 s,
// drained Poisson's ratio 0.3, hold 60 s, transmission at 0, 10, 30, 60 s with water-content
// optics, 20 000 photons each).
#include <chrono>
#include <cstdio>
#include <string>

#include <fmt/format.h>

#include "tocd/sim/study/water_time_course.hpp"

namespace st = tocd::sim::study;

int main(int argc, char** argv) try {
  st::WaterTimeCourseRequest r;
  if (argc > 1) r.displacement_mm = std::stod(argv[1]);
  if (argc > 2) r.permeability.k0_mm4_per_Ns = std::stod(argv[2]);
  if (argc > 3) r.drained_poisson = std::stod(argv[3]);
  if (argc > 4) r.ramp_s = std::stod(argv[4]);
  if (argc > 5) r.steps_per_interval = std::stoi(argv[5]);
  const auto t0 = std::chrono::steady_clock::now();
  const auto points = st::predict_water_time_course(r);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double fe = 0, mesh = 0, mc = 0;
  for (const auto& p : points) {
    fe += p.fe_seconds;
    mesh += p.mesh_seconds;
    mc += p.mc_seconds;
    fmt::print("  t = {:5.1f} s  T = {:.4f} +- {:.4f}  F = {:.5f} N  water out {:.4f} mm3\n", p.time_s, p.T,
               p.T_stderr, p.pin_force_N, p.water_outflow_mm3);
  }
  fmt::print("hold time course ({} points): {:.1f} s wall (FE {:.1f} s, meshes {:.1f} s, MC {:.1f} s)\n",
             points.size(), wall, fe, mesh, mc);
  return 0;
} catch (const std::exception& e) {
  fmt::print(stderr, "poro_bench: {}\n", e.what());
  return 1;
}

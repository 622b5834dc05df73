// Times what `tocdlab fit --data FILE.csv` does on a long file: writes ROWS rows of the published
// skin law in compression (strain 0 to 0.5, 0.5 % Gaussian noise, seed 1) to a temporary CSV,
// reads it back and fits each model, printing the seconds of each. Usage: fit_bench [ROWS]
// (default 20000).
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>

#include <fmt/format.h>
#include <unistd.h>

#include "tocd/sim/material/fit.hpp"

namespace mat = tocd::sim::material;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  const long rows = argc > 1 ? std::strtol(argv[1], nullptr, 10) : 20000;
  if (rows < 10) {
    std::cerr << "fit_bench: ROWS must be at least 10\n";
    return 2;
  }
  const auto path = std::filesystem::temp_directory_path() / fmt::format("fit_bench_{}.csv", ::getpid());
  {
    const auto law = mat::OgdenParameters::published_skin();
    std::mt19937 rng(1);
    std::normal_distribution<double> noise(0.0, 0.005);
    std::ofstream out(path);
    out << "strain,stress_MPa\n";
    for (long k = 0; k < rows; ++k) {
      const double strain = 0.5 * static_cast<double>(k) / static_cast<double>(rows - 1);
      const double stress = -mat::ogden_uniaxial_nominal_stress(law, 1 - strain) * (1 + noise(rng));
      out << fmt::format("{:.9g},{:.9g}\n", strain, stress);
    }
  }
  auto t0 = std::chrono::steady_clock::now();
  const mat::StressStrainData d = mat::read_stress_strain_csv(path);
  std::cout << fmt::format("read {} rows: {:.3f} s\n", d.strain.size(), seconds_since(t0));
  for (const char* model : {"ogden3", "ogden2", "ogden1", "neo-hookean", "mooney-rivlin", "yeoh"}) {
    t0 = std::chrono::steady_clock::now();
    const mat::FitResult r = mat::fit_uniaxial(d.strain, d.stress, mat::parse_fit_model(model));
    std::cout << fmt::format("fit {:<14} {:.3f} s  (rms {:.4g} MPa, R^2 {:.6f}, {})\n", model,
                             seconds_since(t0), r.rms_MPa, r.r_squared,
                             r.converged ? "converged" : "not converged");
  }
  std::filesystem::remove(path);
  return 0;
}

#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tocd/mocks/tissue.hpp"

namespace tocd::mocks {

/// A simulated sample backed by the simulator: its load curve is an axisymmetric FE solve of
/// the pin compression and its transmission the FE + composite mesh + Monte Carlo chain, both
/// tabulated at `displacements_mm` and interpolated linearly in between. It is meant to differ
/// from the model's default tissue (other thickness, stiffness, optics model), so that
/// comparing a simulated run with predictions is not circular.
struct SimTissueSpec {
  double thickness_mm = 2.0;
  /// Shear moduli of the published Ogden fit times this (D_1 divided by it: same Poisson's ratio).
  double stiffness_scale = 1.25;
  std::string optics_model = "graded";  ///< "threshold" | "graded"
  /// Fully cleared skin relative to native (mu_a, mu_s, n; g stays native): the published
  /// study's most cleared state (simulation 11) by default. The graded model moves from native
  /// to it as the compressive log strain grows to full_clearing_strain (8 levels); the threshold
  /// model gives it to every element compressed beyond full_clearing_strain.
  double cleared_mu_a_fraction = 0.6;
  double cleared_mu_s_fraction = 0.6;
  double cleared_n_fraction = 1.1;
  double full_clearing_strain = 0.5;
  std::vector<double> displacements_mm{0.25, 0.5, 0.75, 1.0, 1.25, 1.5};  ///< > 0, ascending
  std::uint64_t photons = 50000;
  std::uint64_t seed = 7;
  int threads = 0;  ///< Monte Carlo threads (0 = all cores)
  /// Called with a line of text per stage (FE, each Monte Carlo point), from the calling thread.
  std::function<void(const std::string&)> progress;
  /// Where prepared tables are cached (sim_tissue_cache.hpp); empty: always prepare afresh.
  std::filesystem::path cache_dir;
};

/// Optical properties of one skin state (mm^-1; g and n dimensionless).
struct SimTissueOptics {
  double mu_a_per_mm = 0, mu_s_per_mm = 0, g = 0, n = 0;
};
/// The fully cleared skin a spec's sample clears to (native skin's optics with the spec's
/// fractions; bit for bit the published cleared state at the default fractions).
SimTissueOptics sim_tissue_cleared_optics(const SimTissueSpec& spec);

/// The tables behind the tissue (displacement 0 first).
struct SimTissueTable {
  std::vector<double> displacement_mm, load_N, transmission, transmission_stderr;
  double seconds = 0;       ///< time this call took (reading the cache or preparing)
  bool from_cache = false;  ///< read from spec.cache_dir rather than computed
  std::string cache_file;   ///< the cache entry read or written ("" without a cache)
};

/// Runs the FE and the Monte Carlo points (blocking; seconds to minutes depending on photons)
/// and returns the tabulated tissue; with spec.cache_dir, a matching cache entry replaces the
/// computation and a fresh computation is stored (a failed store is reported through
/// spec.progress, not thrown). Transmission is relative to the glass-only geometry, as
/// the power meter sees it against a glass-only baseline. Throws tocd::Error subclasses when
/// the simulator fails (bad spec, FE not converging at a requested displacement, meshing).
std::shared_ptr<TissueModel> make_simulated_tissue(const SimTissueSpec& spec,
                                                   SimTissueTable* table = nullptr);

}  // namespace tocd::mocks

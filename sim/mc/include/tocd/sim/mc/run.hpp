#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <vector>

#include "tocd/sim/mc/optics.hpp"
#include "tocd/sim/mc/prepared_mesh.hpp"
#include "tocd/sim/mc/source.hpp"
#include "tocd/sim/parallel/team.hpp"

namespace tocd::sim::mc {

/// Settings of one run. Results depend on (photons, seed, batches) only, never on the number
/// of threads or MPI ranks.
struct RunSettings {
  std::uint64_t photons = 100000;
  std::uint64_t seed = 1;
  int threads = 1;         ///< OpenMP threads (capped at `batches`)
  int batches = 20;        ///< independent batches for standard errors (>= 2)
  double ambient_n = 1.0;  ///< refractive index outside the mesh
  /// Regions with mu_s at or below this (or g = 1) are ballistic: straight flight to the next
  /// face with continuous absorption exp(-mu_a L). Scattering there is neglected.
  double ballistic_mu_s_per_mm = 1e-3;
  double roulette_threshold = 1e-4;  ///< packets lighter than this play Russian roulette...
  int roulette_chance = 10;          ///< ...surviving with probability 1/chance, weight x chance
  bool tally_per_tet = true;         ///< per-tet absorbed weight and fluence (with errors)
  /// Also estimate dT/dmu_a and dT/dmu_s of every region by perturbation Monte Carlo (the
  /// same histories reweighted; docs/mc.md, "Transmittance derivatives"): each packet records
  /// its path length and scattering events per region. Off, the kernel does no extra work.
  /// Either way the random stream, and every other tally, are the same bit for bit.
  bool transmittance_derivatives = false;
  /// Checked between photons by every thread; set it to stop early (result.cancelled).
  const std::atomic<bool>* cancel = nullptr;
  /// Called from the master thread now and then with (photons done, photons asked); under
  /// MPI each member reports its own share scaled to the whole run.
  std::function<void(std::uint64_t, std::uint64_t)> progress;
  /// The processes sharing the run (null: this process alone). Each member runs a contiguous
  /// block of the batches with `threads` threads; every member gets the whole result. A
  /// collective: every member calls run() with the same settings.
  parallel::Team* team = nullptr;
};

/// A mean per launched photon and its standard error from the spread of batch means.
struct Estimate {
  double mean = 0.0;
  double se = 0.0;
};

/// Derivatives of the transmittance with respect to one region's coefficients, in mm (per
/// mm^-1 of mu): means per launched photon with standard errors from the batch spread.
struct TransmittanceDerivative {
  Estimate dT_dmu_a;
  Estimate dT_dmu_s;  ///< 0 for a ballistic region (its scattering is neglected)
};

/// Everything a run measures. Weights are fractions of launched weight (one per photon).
struct Result {
  std::uint64_t photons = 0;  ///< launched (fewer than asked when cancelled)
  std::uint64_t seed = 0;
  int threads = 0;  ///< per process
  int ranks = 1;    ///< processes that shared the run
  int batches = 0;
  bool cancelled = false;

  Estimate transmittance;     ///< exits through bottom faces (outward normal -z on the box bottom)
  Estimate reflectance;       ///< exits through top faces after entering (entry specular excluded)
  Estimate side_loss;         ///< exits through every other boundary face
  Estimate specular;          ///< Fresnel reflection at entry
  Estimate absorbed;          ///< deposited in the mesh
  Estimate roulette_balance;  ///< weight removed by roulette minus weight added to survivors
  Estimate missed;            ///< disk photons whose line missed the mesh (never entered)
  Estimate lost;              ///< packets stopped by the step guard (numerically stuck); should be 0
  std::map<std::int32_t, Estimate> exit_by_marker;      ///< exits per boundary marker (0 = none)
  std::map<std::int32_t, Estimate> absorbed_by_region;  ///< per region id
  /// Per region id, when RunSettings::transmittance_derivatives was set (else empty).
  std::map<std::int32_t, TransmittanceDerivative> transmittance_derivatives;

  /// Per tet (empty when tally_per_tet is off): absorbed weight and fluence
  /// Phi = w_a / (V mu_a) in mm^-2 per launched weight (0 where mu_a = 0).
  std::vector<double> absorbed_per_tet, absorbed_per_tet_se;
  std::vector<double> fluence_per_tet, fluence_per_tet_se;

  /// launched - (specular + exited + absorbed + roulette_balance + missed + lost), divided by
  /// launched: zero up to round-off.
  double energy_balance_error = 0.0;

  std::uint64_t events = 0;     ///< scattering events
  std::uint64_t face_hits = 0;  ///< packet arrivals at a tet face (crossings and reflections)
  double seconds = 0.0;
  double photons_per_second = 0.0;
  double events_per_second = 0.0;
};

/// Exact sums over some batches of a run (fixed-point words, see docs/mc.md "Reduction"):
/// the tallies of different batches add element-wise, in any order, to the same total.
struct Tallies {
  std::vector<std::int64_t> words;
  int threads = 0;  ///< threads that ran them (not part of the sums)
};

/// Runs batches [first_batch, last_batch) of the run `settings` describes (settings.team is
/// not used) and returns their exact tallies. Throws like run().
Tallies run_batches(const PreparedMesh& mesh, const Optics& optics, const Source& source,
                    const RunSettings& settings, int first_batch, int last_batch);

/// The result from the summed tallies of a run's batches (all of them, or fewer when a run
/// was cancelled). Timing fields are left zero. Throws tocd::Error when the tallies do not
/// belong to this mesh and these settings.
Result finish(const PreparedMesh& mesh, const Optics& optics, const RunSettings& settings,
              const Tallies& tallies);

/// Runs the Monte Carlo. Throws OpticsError when a region of the mesh has no optics,
/// SourceError when the source cannot enter the mesh, tocd::ConfigError on bad settings.
Result run(const PreparedMesh& mesh, const Optics& optics, const Source& source, const RunSettings& settings);

}  // namespace tocd::sim::mc

#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/sim/study/predictor.hpp"

namespace tocd::sim::study {

/// One simulation of a study: an id, a short optics label and the full request.
struct StudyCase {
  int id = 0;
  std::string optics_label;  ///< "glass only", "native", "mu_a 80%", "graded", ...
  PredictionRequest request;
};

/// Settings shared by every simulation of a study (the rest of each request is per case).
struct StudySettings {
  std::uint64_t photons = 1000000;
  std::uint64_t seed = 1;
  std::string mesh_preset = "fast";
  int threads = 0;
  int batches = 20;
  double max_edge_mm = 0;
  std::string fluence_dir;                       ///< per-simulation fluence files when not empty
  vtk::Format vtu_format = vtk::Format::binary;  ///< of the fluence .vtu files
  /// Across MPI ranks: a simulation with at least this many photons has its batches shared
  /// among the ranks; smaller ones run whole on one rank. Results are the same either way.
  std::uint64_t split_photons = 10'000'000;
};

/// The published study (model note): 0 = glass-only baseline; 1..3 native skin at
/// 0, 0.625 and 1.5 mm; 4..11 at 1.5 mm with the compressed region's mu_a, mu_s, n changed.
/// `thickness_mm` other than 2.5 keeps the displacements' nominal strains (d / thickness).
std::vector<StudyCase> paper_cases(const StudySettings& settings, double thickness_mm = 2.5);

/// A named compressed-region optics: "native", "a80", "a60", "s80", "s60", "n105", "n110",
/// "a80s80n105", "a60s60n110" (the study's changes), "cleared" (= a60s60n110), "graded"
/// (strain-graded model), or "MU_A/MU_S/N" in mm^-1. Throws tocd::ConfigError.
void apply_optics(const std::string& name, PredictionRequest& request, std::string& label);

/// Every combination of displacement x thickness x optics, after a glass-only baseline
/// (id 0) when `with_baseline`; ids count from 1.
std::vector<StudyCase> sweep_cases(const StudySettings& settings, const std::vector<double>& displacements_mm,
                                   const std::vector<double>& thicknesses_mm,
                                   const std::vector<std::string>& optics, bool with_baseline = true);

struct StudyRow {
  StudyCase c;
  Prediction p;
  double strain = 0;  ///< nominal strain d / thickness
  /// T relative to the reference rows (NaN when the reference is absent), with standard
  /// errors propagated as independent: se(a/b) = (a/b) sqrt((se_a/a)^2 + (se_b/b)^2).
  double rel_a = 0, rel_a_se = 0, rel_b = 0, rel_b_se = 0;
  double seconds = 0;  ///< wall time of this simulation (FE + mesh + MC)
};

struct StudyTable {
  std::vector<StudyRow> rows;
  int ref_a = 0, ref_b = 3;  ///< ids the relative columns refer to (-1: none)
  StudySettings settings;
  double seconds = 0;
  std::string fluence_series;  ///< the .pvd listing the fluence files, when they were written
};

/// Writes fluence.pvd beside the fluence files (the study's fluence_dir), the ParaView series of the table's
/// fluence .vtu files (one dataset per simulation, timestep = simulation id), and returns its path; does
/// nothing and returns "" when the table has no fluence files. run_study calls it. Throws tocd::Error.
std::string write_fluence_series(const StudyTable& table);

/// Runs the cases in order on `predictor` (FE and meshes shared through its caches) and
/// fills the relative columns. `progress` is called after each row.
StudyTable run_study(Predictor& predictor, const std::vector<StudyCase>& cases, const StudySettings& settings,
                     int ref_a = 0, int ref_b = 3, const std::function<void(const StudyRow&)>& progress = {});

/// run_study across the members of `team`, a collective: every member calls it with the same
/// cases. Member 0 hands out the work as members ask for it (whole simulations, or blocks of
/// batches of the large ones, see StudySettings::split_photons), sums the exact Monte Carlo
/// tallies and assembles the rows; its table equals run_study's on one process in every
/// number but the timings. Other members return an empty table. With a team of one this
/// is run_study.
StudyTable run_study(Predictor& predictor, const std::vector<StudyCase>& cases, const StudySettings& settings,
                     int ref_a, int ref_b, const std::function<void(const StudyRow&)>& progress,
                     parallel::Team& team);

/// Recomputes the relative columns from the rows (used by run_study; public for tests).
void fill_relatives(StudyTable& table);

std::string format_table(const StudyTable& table);       ///< the table printed by `tocdlab study`
std::string table_header(int ref_a = 0, int ref_b = 3);  ///< its two header lines
std::string format_row(const StudyRow& row);             ///< one line of it
nlohmann::json to_json(const StudyTable& table);         ///< every number shown, plus configs and artefacts
std::string to_csv(const StudyTable& table);             ///< one line per simulation, header first

}  // namespace tocd::sim::study

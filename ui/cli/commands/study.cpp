// `tocdlab study paper|sweep`: the published parametric study and sweeps (docs/study.md).
#include "tocd/sim/study/study.hpp"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "numeric_options.hpp"
#include "output_naming.hpp"
#include "output_paths.hpp"
#include "progress.hpp"
#include "tocd/core/atomic_file.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/fe/inverse_fit.hpp"
#include "tocd/sim/parallel/team.hpp"
#include "tocd/sim/study/sensitivity.hpp"
#include "vtu_format_option.hpp"

namespace cli = tocd::cli;

namespace {

namespace st = tocd::sim::study;

struct StudyOptions {
  st::StudySettings settings;
  std::string output_path;
  bool json = false;
  double thickness_mm = 2.5;
  std::vector<double> displacements, thicknesses;
  std::vector<std::string> optics;
  bool no_baseline = false;
};

// Rows appear on stderr as each simulation finishes (progress); the whole table goes to stdout
// at the end, as text or with --json as one JSON document, and to -o FILE as CSV or JSON.
void run(const StudyOptions& o, const std::vector<st::StudyCase>& cases, int ref_a, int ref_b) {
  auto& team = tocd::sim::parallel::world();
  std::optional<cli::ProgressBar> bar;
  if (team.rank() == 0) {
    bar.emplace("study", cases.size(), "simulations");
    bar->note(fmt::format("{} simulations, {} photons each, mesh '{}', seed {}", cases.size(),
                          o.settings.photons, o.settings.mesh_preset, o.settings.seed));
    bar->note(st::table_header(ref_a, ref_b));
  }
  // Under mpirun the ranks share the simulations; rank 0 alone prints and writes files.
  st::Predictor predictor(1, &team);
  std::uint64_t rows_done = 0;
  const st::StudyTable table = st::run_study(
      predictor, cases, o.settings, ref_a, ref_b,
      [&](const st::StudyRow& r) {
        if (!bar) return;
        bar->note(st::format_row(r));
        bar->update(++rows_done);
      },
      team);
  if (team.rank() != 0) return;
  bar->update(cases.size());
  bar->finish();
  if (!o.output_path.empty()) {
    const bool as_json = std::filesystem::path(o.output_path).extension() == ".json";
    tocd::write_file_atomically(o.output_path, as_json
                                                   ? cli::to_naming_table(st::to_json(table)).dump(2) + "\n"
                                                   : cli::to_naming_table_csv(st::to_csv(table)));
    cli::announce_file(as_json ? "table (JSON)" : "table (CSV)", o.output_path);
  }
  if (!o.settings.fluence_dir.empty()) {
    // The predictor wrote them as each simulation finished: say where, and how many.
    std::size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(o.settings.fluence_dir))
      files += e.is_regular_file() ? 1 : 0;
    cli::announce_file("fluence files (slices CSV, mesh VTU/PVD)",
                       fmt::format("{} ({} files)", o.settings.fluence_dir, files));
  }
  if (o.json) {
    cli::print_json(st::to_json(table));
    return;
  }
  std::cout << st::table_header(ref_a, ref_b);
  for (const auto& r : table.rows) std::cout << st::format_row(r);
  std::cout << fmt::format("total {:.1f} s\n", table.seconds) << std::flush;
}

void add_common(CLI::App* cmd, StudyOptions& o) {
  cli::add_photons_option(*cmd, "--photons", o.settings.photons, "photons per simulation");
  cmd->add_option("--mesh", o.settings.mesh_preset, "mesh preset: fast | paper")
      ->check(CLI::IsMember({"fast", "paper"}))
      ->capture_default_str();
  cmd->add_option("--max-edge", o.settings.max_edge_mm, "override the preset's surface edge length (mm)")
      ->check(cli::real_above(0.0, 100.0));
  cli::add_threads_option(*cmd, o.settings.threads,
                          "Monte Carlo threads (0 = all cores; results do not depend on it)");
  cli::add_seed_option(*cmd, o.settings.seed, "random seed (the same for every simulation)");
  cmd->add_option("--batches", o.settings.batches, "batches for standard errors")
      ->check(cli::whole_in(std::int64_t{2}, std::int64_t{1000000}))
      ->capture_default_str();
  cmd->add_option(
         "--split-photons", o.settings.split_photons,
         "under MPI: simulations with at least this many photons share their batches among the ranks")
      ->check(cli::whole_in(std::uint64_t{1}, std::numeric_limits<std::uint64_t>::max()))
      ->capture_default_str();
  cmd->add_flag("--json", o.json,
                "print every number of the table (and each run's config) as JSON on stdout");
  cmd->add_option("-o,--output", o.output_path,
                  "also write the table to FILE: JSON if it ends in .json, else CSV")
      ->check(cli::output_file());
  cmd->add_option("--csv", o.output_path, "deprecated: use -o FILE.csv")
      ->check(cli::output_file())
      ->group("");
  cmd->add_option("--fluence-dir", o.settings.fluence_dir,
                  "write per-tet fluence (.vtu) and horizontal/vertical slices (.csv) per simulation, and "
                  "their ParaView series fluence.pvd, here")
      ->check(cli::output_dir());
  tocd::cli::add_vtu_format_option(cmd, o.settings.vtu_format);
}

struct SensitivityOptions {
  st::PredictionRequest base;
  std::string fit_path;
  bool json = false;
};

// The fitted law of `tocdlab fit --method fe --json` and the laws at its confidence ellipsoid's
// axis ends.
void read_fit(const std::string& path, SensitivityOptions& o,
              std::vector<std::pair<std::string, tocd::sim::material::OgdenParameters>>& laws) {
  std::ifstream in(path);
  if (!in) throw tocd::ConfigError(fmt::format("--fit {}: cannot open the file", path));
  try {
    auto fit = tocd::sim::fe::fitted_laws_from_json(nlohmann::json::parse(in));
    o.base.material = fit.law;
    laws = std::move(fit.confidence_laws);
  } catch (const nlohmann::json::exception& e) {
    throw tocd::ConfigError(fmt::format(
        "--fit {}: expected the output of `tocdlab fit --method fe --json` ({})", path, e.what()));
  }
}

void run_sensitivity(SensitivityOptions o) {
  std::vector<std::pair<std::string, tocd::sim::material::OgdenParameters>> laws;
  if (!o.fit_path.empty()) read_fit(o.fit_path, o, laws);
  st::validate(o.base);
  const auto variants = st::sensitivity_variants(o.base, laws);
  std::cerr << fmt::format("sensitivity of T at d = {} mm: base + {} variants, {} photons each, seed {}\n",
                           o.base.displacement_mm, variants.size(), o.base.photons, o.base.seed);
  st::Predictor predictor(1);
  const auto table = st::run_sensitivity(predictor, o.base, variants, [](const std::string& line) {
    std::cerr << line << '\n' << std::flush;
  });
  if (o.json) {
    std::cerr << st::format_sensitivity(table);
    std::cout << st::to_json(table).dump(2) << '\n';
  } else {
    std::cout << st::format_sensitivity(table);
  }
}

void install_sensitivity(CLI::App* study) {
  auto* cmd = study->add_subcommand(
      "sensitivity", "dT of one step when one modelling choice at a time is changed (common random numbers)");
  auto o = std::make_shared<SensitivityOptions>();
  o->base.displacement_mm = 1.5;
  o->base.photons = 1000000;
  cmd->add_option("--displacement", o->base.displacement_mm, "pin displacement (mm)")
      ->check(cli::real_in(0.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--thickness", o->base.thickness_mm, "skin thickness (mm)")
      ->check(cli::real_above(0.0, 100.0))
      ->capture_default_str();
  cli::add_photons_option(*cmd, "--photons", o->base.photons, "photons per simulation");
  cli::add_seed_option(*cmd, o->base.seed, "random seed (the same for every variant)");
  cmd->add_option("--batches", o->base.batches, "batches (the standard errors come from their spread)")
      ->check(cli::whole_in(std::int64_t{2}, std::int64_t{1000000}))
      ->capture_default_str();
  cli::add_threads_option(*cmd, o->base.threads, "batches run at once (0 = all cores)");
  cmd->add_option("--mesh", o->base.mesh_preset, "base mesh preset: fast | paper")
      ->check(CLI::IsMember({"fast", "paper"}))
      ->capture_default_str();
  cmd->add_option("--optics", o->base.optics_model, "base optics model: threshold | graded")
      ->check(CLI::IsMember({"threshold", "graded"}))
      ->capture_default_str();
  cmd->add_option(
      "--fit", o->fit_path,
      "a `tocdlab fit --method fe --json` file: its law is the base, its confidence laws vary it");
  cmd->add_flag("--json", o->json, "one JSON document on stdout (the table goes to stderr)");
  cmd->callback([o] { run_sensitivity(*o); });
}

void install_study(CLI::App& root) {
  auto* study =
      root.add_subcommand("study", "Parametric optical studies of pin compression (see docs/study.md)");
  study->require_subcommand(1);
  auto o = std::make_shared<StudyOptions>();

  auto* paper = study->add_subcommand("paper", "The published study: simulations 0..11");
  add_common(paper, *o);
  paper->add_option("--thickness", o->thickness_mm, "skin thickness (mm); displacements keep their strains")
      ->check(cli::real_above(0.0, 100.0))
      ->capture_default_str();
  paper->callback([o] { run(*o, st::paper_cases(o->settings, o->thickness_mm), 0, 3); });

  auto* sweep = study->add_subcommand("sweep", "Every displacement x thickness x optics combination");
  add_common(sweep, *o);
  sweep->add_option("--displacements", o->displacements, "pin displacements (mm), comma separated")
      ->check(cli::real_in(0.0, 100.0))
      ->delimiter(',')
      ->required();
  sweep->add_option("--thickness", o->thicknesses, "skin thicknesses (mm), comma separated (default 2.5)")
      ->check(cli::real_above(0.0, 100.0))
      ->delimiter(',');
  sweep
      ->add_option("--optics", o->optics,
                   "compressed-region optics, comma separated: native, a80, a60, s80, s60, n105, n110, "
                   "a80s80n105, a60s60n110, cleared, graded, MU_A/MU_S/N (default native)")
      ->delimiter(',');
  install_sensitivity(study);
  sweep->add_flag("--no-baseline", o->no_baseline, "skip the glass-only baseline (sim 0)");
  sweep->callback([o] {
    run(*o, st::sweep_cases(o->settings, o->displacements, o->thicknesses, o->optics, !o->no_baseline),
        o->no_baseline ? -1 : 0, 1);
  });
}

}  // namespace

TOCD_CLI_COMMAND(study, install_study);

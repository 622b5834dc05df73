// `tocdlab predict`: transmission for one compression step (FE + tet mesh + Monte Carlo).
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
#include "predict_series.hpp"
#include "predict_water.hpp"
#include "progress.hpp"
#include "tocd/analysis/sim_step_predictor.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/parallel/team.hpp"
#include "tocd/sim/study/predictor.hpp"
#include "tocd/sim/study/study.hpp"
#include "vtu_format_option.hpp"

namespace cli = tocd::cli;

namespace {

namespace st = tocd::sim::study;

struct PredictOptions {
  st::PredictionRequest request;
  std::string compressed = "cleared", config_path;
  bool json = false;
  tocd::cli::RunSeriesOptions series;    // --db/--run/--output-dir: a run's steps as a .pvd series
  tocd::cli::PredictWaterOptions water;  // --optics water: T(t) over a hold
};

void print_prediction(const st::PredictionRequest& r, const st::Prediction& p) {
  std::cout << fmt::format("d = {} mm into {} mm skin, optics {} ({}), {} photons, seed {}, mesh '{}'\n",
                           r.displacement_mm, r.thickness_mm, r.optics_model,
                           r.optics_model == "graded" ? "strain-graded" : r.compressed_optics.name, r.photons,
                           r.seed, r.mesh_preset);
  std::cout << fmt::format(
      "  T          {:.6f} +- {:.6f}\n  side loss  {:.6f} +- {:.6f} (slide edges {:.6f} +- {:.6f})\n", p.T,
      p.T_stderr, p.side_loss, p.side_loss_stderr, p.side_loss_slide, p.side_loss_slide_stderr);
  std::cout << fmt::format("  reflected  {:.6f}, absorbed {:.6f}, specular {:.6f}\n", p.reflectance,
                           p.absorbed, p.specular);
  if (p.fe_summary.contains("force_N"))
    std::cout << fmt::format("  FE: force {:.4g} N, compressed volume {:.4g} mm^3\n",
                             p.fe_summary["force_N"].get<double>(),
                             p.fe_summary["compressed_volume_mm3"].get<double>());
  std::cout << fmt::format("  {} tets; FE {:.1f} s, mesh {:.1f} s, Monte Carlo {:.1f} s\n", p.tets,
                           p.fe_seconds, p.mesh_seconds, p.mc_seconds);
}

st::ConfigDocument read_config(const PredictOptions& o) {
  std::ifstream in(o.config_path);
  if (!in) throw tocd::ConfigError(fmt::format("cannot read prediction config {}", o.config_path));
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw tocd::ConfigError(fmt::format("{}: not JSON ({})", o.config_path, e.what()));
  }
  st::ConfigDocument d = st::config_document_from_json(j);
  // Threads and output files do not change the answer: they come from this command line.
  for (st::PredictionRequest* r : {&d.step, d.baseline ? &*d.baseline : nullptr}) {
    if (!r) continue;
    r->threads = o.request.threads;
    r->fluence_dir = o.request.fluence_dir;
    r->vtu_format = o.request.vtu_format;
  }
  if (d.baseline) d.baseline->fluence_stem = "baseline";
  return d;
}

// A run's stored prediction: T(step) / T(baseline), computed as the run engine computes it.
void run_relative(const st::ConfigDocument& d, const st::Prediction& p, const st::Prediction& b, bool json) {
  const auto rel = tocd::analysis::relative_to_baseline(p.T, p.T_stderr, b.T, b.T_stderr);
  if (json) {
    nlohmann::json j = {{"quantity", d.quantity},
                        {"T", rel.T},
                        {"T_se", rel.T_stderr},
                        {"config", {{"quantity", d.quantity}, {"step", p.config}, {"baseline", b.config}}},
                        {"step", st::to_json(p)},
                        {"baseline", st::to_json(b)}};
    cli::print_json(j);
    return;
  }
  std::cout << fmt::format("T = {}: {:.6f} +- {:.6f}\nstep: ",
                           d.quantity.empty() ? "T(step) / T(baseline)" : d.quantity, rel.T, rel.T_stderr);
  print_prediction(d.step, p);
  std::cout << "baseline: ";
  print_prediction(*d.baseline, b);
}

void run_predict(PredictOptions o) {
  if (!o.series.db.empty()) {
    o.series.threads = o.request.threads;
    o.series.format = o.request.vtu_format;
    o.series.json = o.json;
    tocd::cli::predict_run_series(o.series);
    return;
  }
  st::PredictionRequest r = o.request;
  std::optional<st::ConfigDocument> document;
  if (!o.config_path.empty()) {
    document = read_config(o);
    r = document->step;
  } else if (r.optics_model == "threshold") {
    std::string label;
    st::apply_optics(o.compressed, r, label);
  }
  st::Predictor predictor(1, &tocd::sim::parallel::world());  // under mpirun the ranks share the photons
  // FE and meshing cannot count their work and show as elapsed time; the Monte Carlo then
  // counts photons (a bar with rate and ETA).
  auto predict = [&](const st::PredictionRequest& q, const char* what) {
    if (tocd::sim::parallel::world().rank() != 0) return predictor.predict(q);
    cli::PhasedProgress progress(fmt::format("predict: {} (FE + mesh)", what),
                                 fmt::format("predict: {} Monte Carlo", what), "photons");
    st::PredictionRequest observed = q;
    observed.mc_progress = [&progress](std::uint64_t done, std::uint64_t total) {
      progress.update(done, total);
    };
    st::Prediction p = predictor.predict(observed);
    progress.finish();
    return p;
  };
  const st::Prediction p = predict(r, "step");
  if (!p.fluence.is_null())
    for (const char* k : {"vtu", "horizontal_csv", "vertical_csv"})
      if (p.fluence.contains(k))
        cli::announce_file(fmt::format("fluence {}", k), p.fluence[k].get<std::string>());
  if (document && document->baseline) {
    run_relative(*document, p, predict(*document->baseline, "baseline"), o.json);
    return;
  }
  if (o.json) {
    cli::print_json(st::to_json(p));
    return;
  }
  print_prediction(r, p);
}

// The step's geometry, optics, Monte Carlo and output options.
void add_step_options(CLI::App* cmd, PredictOptions& o) {
  auto& r = o.request;
  cmd->add_option("--displacement", r.displacement_mm, "pin displacement into the skin (mm)")
      ->check(cli::real_in(0.0, 100.0))
      ->capture_default_str();
  cmd->add_option("--thickness", r.thickness_mm, "skin thickness (mm)")
      ->check(cli::real_above(0.0, 100.0))
      ->capture_default_str();
  cli::add_photons_option(*cmd, "--photons", r.photons, "photons");
  cli::add_seed_option(*cmd, r.seed, "random seed");
  cmd->add_option("--optics", r.optics_model,
                  "optics model: threshold | graded | water (T over a hold: biphasic FE, water-content "
                  "optics; docs/water.md)")
      ->check(CLI::IsMember({"threshold", "graded", "water"}))
      ->capture_default_str();
  cmd->add_option("--compressed-optics", o.compressed,
                  "threshold model: optics of the compressed region (native, a80, ..., cleared, MU_A/MU_S/N)")
      ->capture_default_str();
  cmd->add_option("--graded-bins", r.graded.bins, "graded model: optics levels")
      ->check(cli::whole_in(std::int64_t{1}, std::int64_t{1000}))
      ->capture_default_str();
  cmd->add_option("--mesh", r.mesh_preset, "mesh preset: fast | paper")
      ->check(CLI::IsMember({"fast", "paper"}))
      ->capture_default_str();
  cmd->add_option("--max-edge", r.max_edge_mm, "override the preset's surface edge length (mm)")
      ->check(cli::real_above(0.0, 100.0));
  cmd->add_option("--tip-edge", r.tip_edge_mm, "override the pin tip's segment length (mm)")
      ->check(cli::real_above(0.0, 100.0));
  cmd->add_option("--pin-length", r.pin_length_mm, "pin length tip to top face (mm)")
      ->check(cli::real_above(0.0, 1000.0))
      ->capture_default_str();
  cli::add_threads_option(*cmd, r.threads, "Monte Carlo threads (0 = all cores)");
  cmd->add_flag("--baseline", r.baseline, "glass only: pin tip on the slide, no skin");
  cmd->add_option("--config", o.config_path,
                  "reproduce a prediction from its config JSON, its --json output, or a run's stored "
                  "predictions.config_json (T relative to the glass-only baseline)");
  cmd->add_option("--fluence-dir", r.fluence_dir, "write fluence .vtu and slice CSVs here")
      ->check(cli::output_dir());
  tocd::cli::add_vtu_format_option(cmd, r.vtu_format);
  cmd->add_flag("--json", o.json, "machine-readable output with config and artefacts");
}

// --db/--run/--output-dir: a recorded run's stored predictions again, as a .pvd series.
void add_series_options(CLI::App* cmd, PredictOptions& o) {
  auto* db =
      cmd->add_option("--db", o.series.db, "with --run and --output-dir: re-run a run's stored predictions");
  auto* run = cmd->add_option("--run", o.series.run, "run id whose steps to re-run (see tocdlab runs)")
                  ->check(cli::whole_in(std::int64_t{1}, std::numeric_limits<std::int64_t>::max()));
  auto* dir = cmd->add_option("--output-dir", o.series.output_dir,
                              "write each step's fluence .vtu and the series run.pvd here")
                  ->check(cli::output_dir());
  db->needs(run)->needs(dir)->excludes("--config");
  run->needs(db);
  dir->needs(db);
}

// The options of --optics water only; the callback refuses them with other optics.
std::vector<const CLI::Option*> add_water_options(CLI::App* cmd, PredictOptions& o) {
  auto& w = o.water;
  auto* hold =
      cmd->add_option("--hold-s", w.hold_s, "water optics: length of the hold (s); T at 0, 1/6, 1/2, 1 of it")
          ->check(cli::real_above(0.0, 1e6))
          ->capture_default_str();
  auto* times =
      cmd->add_option("--times", w.times_s, "water optics: time points into the hold (s), ascending")
          ->delimiter(',')
          ->excludes(hold);
  auto* ramp =
      cmd->add_option("--ramp-s", w.request.ramp_s, "water optics: time the pin takes to its depth (s)")
          ->check(cli::real_above(0.0, 1e6))
          ->capture_default_str();
  auto* nu = cmd->add_option("--drained-poisson", w.request.drained_poisson,
                             "water optics: drained Poisson's ratio of the skeleton")
                 ->check(cli::real_in(-0.99, 0.4999))
                 ->capture_default_str();
  auto* k0 = cmd->add_option("--k0", w.request.permeability.k0_mm4_per_Ns,
                             "water optics: permeability at the reference state (mm^4/(N s))")
                 ->check(cli::real_above(0.0, 1e6))
                 ->capture_default_str();
  return {hold, times, ramp, nu, k0};
}

void install_predict(CLI::App& root) {
  auto* cmd =
      root.add_subcommand("predict", "Predict transmission for one pin-compression step (see docs/study.md)");
  auto o = std::make_shared<PredictOptions>();
  add_step_options(cmd, *o);
  add_series_options(cmd, *o);
  const auto water_only = add_water_options(cmd, *o);
  cmd->callback([o, cmd, water_only] {
    const bool water = o->request.optics_model == "water";
    if (!water) {
      for (const CLI::Option* opt : water_only)
        if (opt->count() > 0) throw CLI::ValidationError(opt->get_name(), "needs --optics water");
      run_predict(*o);
      return;
    }
    for (const char* other : {"--config", "--db", "--baseline", "--compressed-optics", "--graded-bins",
                              "--fluence-dir", "--max-edge", "--tip-edge", "--pin-length"})
      if (cmd->count(other) > 0) throw CLI::ValidationError(other, "is not used with --optics water");
    auto& q = o->water.request;
    const auto& given = o->request;
    // The time course's own defaults (docs/water.md) unless given here.
    if (cmd->count("--displacement") > 0) q.displacement_mm = given.displacement_mm;
    if (cmd->count("--thickness") > 0) q.thickness_mm = given.thickness_mm;
    if (cmd->count("--photons") > 0) q.photons = given.photons;
    q.seed = given.seed;
    q.threads = given.threads;
    q.mesh_preset = given.mesh_preset;
    o->water.json = o->json;
    tocd::cli::run_predict_water(o->water);
  });
}

}  // namespace

TOCD_CLI_COMMAND(predict, install_predict);

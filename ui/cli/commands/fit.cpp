// `tocdlab fit`: fit a hyperelastic law to nominal stress-strain data (docs/fe.md, "Fitting").
#include "tocd/sim/material/fit.hpp"

#include <iostream>
#include <limits>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "fit_fe.hpp"
#include "numeric_options.hpp"
#include "output_naming.hpp"
#include "progress.hpp"
#include "tocd/analysis/run_stress_strain.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/sim/fe/inverse_fit.hpp"

namespace cli = tocd::cli;

namespace {

struct FitCliOptions {
  /// What both methods read (--data, --db, --run, --model, --pin-radius, --poisson, --json)
  /// and the options of --method fe alone.
  tocd::cli::FitFeOptions fe;
  std::size_t bins = 40;  ///< --method fe has its own default (FitFeOptions::bins)
  bool signed_data = false;
  std::string method = "uniaxial";
};

void run_fit(const FitCliOptions& o) {
  namespace mat = tocd::sim::material;
  const tocd::cli::FitFeOptions& in = o.fe;
  if (o.method == "fe") {
    if (in.csv.empty() && in.db.empty() && in.datasets.empty())
      throw tocd::ConfigError("--method fe needs --db FILE --run ID, --csv FILE or --dataset MODE:FILE");
    if (!in.csv.empty() && !in.db.empty()) throw tocd::ConfigError("give --csv or --db, not both");
    tocd::cli::run_fit_fe(in);
    return;
  }
  if (!in.datasets.empty()) throw tocd::ConfigError("--dataset needs --method fe");
  if (in.csv.empty() == in.db.empty())
    throw tocd::ConfigError("give exactly one of --data FILE.csv or --db FILE --run ID");
  mat::StressStrainData d;
  if (!in.csv.empty()) {
    d = mat::read_stress_strain_csv(in.csv);
  } else {
    if (in.run <= 0) throw tocd::ConfigError("--db needs --run ID (see tocdlab runs --db FILE)");
    const auto ss =
        tocd::analysis::stress_strain_from_run(tocd::db::Reader(in.db), in.run, in.pin_radius, o.bins);
    d.strain = ss.strain;
    d.stress = ss.stress_MPa;
    if (!cli::progress_quiet())
      std::cerr << fmt::format(
          "run {}: {} load/displacement pairs on the loading branch, {} mm sample, pin radius {} mm\n",
          in.run, ss.pairs_used, ss.thickness_mm, ss.pin_radius_mm);
  }
  mat::FitOptions opt;
  opt.compression = !o.signed_data;
  opt.poisson_ratio = in.poisson;
  const mat::FitResult r = mat::fit_uniaxial(d.strain, d.stress, mat::parse_fit_model(in.model), opt);
  if (in.json) {
    nlohmann::json j;
    j["model"] = mat::to_string(r.model);
    j["points"] = d.strain.size();
    for (std::size_t k = 0; k < r.names.size(); ++k) j["parameters"][r.names[k]] = r.values[k];
    j["D"] = r.D;
    if (r.has_ogden_form)
      j["ogden"] = {{"mu_MPa", r.ogden.mu}, {"alpha", r.ogden.alpha}, {"D_per_MPa", r.ogden.D}};
    j["rms_MPa"] = r.rms_MPa;
    j["r_squared"] = r.r_squared;
    j["max_abs_residual_MPa"] = r.max_abs_residual_MPa;
    j["residuals_MPa"] = r.residuals;
    j["converged"] = r.converged;
    j["stability"] = tocd::sim::fe::to_json(r.stability);
    cli::print_json(j);
    return;
  }
  std::cout << fmt::format("{} fit to {} points ({})\n", mat::to_string(r.model), d.strain.size(),
                           opt.compression ? "uniaxial compression magnitudes" : "signed nominal data");
  for (std::size_t k = 0; k < r.names.size(); ++k)
    std::cout << fmt::format("  {:<7} {:>14.6g}\n", r.names[k], r.values[k]);
  std::cout << fmt::format("  {:<7} {:>14.6g}  (1/MPa, from Poisson's ratio {})\n", "D1", r.D[0], in.poisson);
  std::cout << fmt::format("  rms residual {:.4g} MPa, max {:.4g} MPa, R^2 {:.6f}\n", r.rms_MPa,
                           r.max_abs_residual_MPa, r.r_squared);
  std::cout << fmt::format("  Drucker stability over stretch [{:.3g}, {:.3g}]: {}\n", r.stability.lambda_min,
                           r.stability.lambda_max,
                           r.stability.stable ? "stable" : "UNSTABLE (" + r.stability.first_failure + ")");
}

void install_fit(CLI::App& root) {
  auto* cmd =
      root.add_subcommand("fit", "Fit a hyperelastic law to nominal stress-strain data (see docs/fe.md)");
  auto o = std::make_shared<FitCliOptions>();
  cmd->add_option("--data", o->fe.csv,
                  "input CSV, two columns: strain, stress [MPa] (compression magnitudes by default)");
  cmd->add_option("--csv", o->fe.csv, "deprecated: use --data FILE.csv")->group("");
  cmd->add_option("--db", o->fe.db, "measurement database: fit a recorded run's load/displacement instead");
  cmd->add_option("--run", o->fe.run, "run id in --db")
      ->check(cli::whole_in(std::int64_t{1}, std::numeric_limits<std::int64_t>::max()));
  cmd->add_option("--pin-radius", o->fe.pin_radius, "pin radius [mm] for stress = load / (pi r^2) (--db)")
      ->check(cli::real_above(0.0, 100.0))
      ->capture_default_str();
  auto* bins = cmd->add_option("--bins", o->bins, "strain bins the run's samples are averaged in (--db)")
                   ->check(cli::whole_in(std::uint64_t{1}, std::uint64_t{100000}))
                   ->capture_default_str();
  cmd->add_option("--model", o->fe.model, "ogden1 | ogden2 | ogden3 | neo-hookean | mooney-rivlin | yeoh")
      ->capture_default_str();
  cmd->add_option("--poisson", o->fe.poisson, "Poisson's ratio that sets D1 from the fitted shear modulus")
      ->check(cli::real_above(-1.0, 0.5))
      ->capture_default_str();
  cmd->add_flag("--signed", o->signed_data, "data are signed nominal strain/stress (tension positive)");
  cmd->add_flag("--json", o->fe.json, "machine-readable output");
  // The inverse FE fit (docs/fe.md, "Inverse FE fit").
  cmd->add_option("--method", o->method,
                  "uniaxial: nominal stress = load / pin area (fast); fe: the pin-compression FE in the loop")
      ->check(CLI::IsMember({"uniaxial", "fe"}))
      ->capture_default_str();
  cmd->add_option(
         "--thickness", o->fe.thickness,
         "sample thickness [mm] (--method fe with --csv of displacement [mm], load [N]; --db: the run's)")
      ->check(cli::real_above(0.0, 100.0));
  cmd->add_option("--kinematics", o->fe.kinematics,
                  "FE kinematics: axi | plane-strain | plane-stress (--method fe)")
      ->capture_default_str();
  cmd->add_option("--bottom", o->fe.bottom, "skin bottom: bonded | sliding (--method fe)")
      ->capture_default_str();
  cmd->add_option("--refine", o->fe.refine, "FE mesh refinement (--method fe; 0.5 = coarse and 4x faster)")
      ->check(cli::real_above(0.0, 16.0))
      ->capture_default_str();
  cmd->add_flag("--fit-d", o->fe.fit_D, "fit D1 too instead of setting it from --poisson (--method fe)");
  cmd->add_option("--confidence", o->fe.confidence, "level of the parameter intervals (--method fe)")
      ->check(cli::real_above(0.0, 0.9999))
      ->capture_default_str();
  cmd->add_option("--weight", o->fe.weight, "weight of the --db/--csv dataset in a joint fit (--method fe)")
      ->check(cli::real_above(0.0, 1e12))
      ->capture_default_str();
  auto* points = cmd->add_option("--points", o->fe.points,
                                 "a run's loads the FE matches: held (each step's hold, nearest "
                                 "equilibrium) | loading (the loading curve) (--method fe --db)")
                     ->check(CLI::IsMember({"held", "loading"}))
                     ->capture_default_str();
  cmd->add_option("--dataset", o->fe.datasets,
                  "another dataset for a joint fit, MODE:FILE[:WEIGHT]; MODE uniaxial | equibiaxial | "
                  "simple-shear (CSV: signed nominal strain or shear, nominal stress MPa) or pin (CSV: "
                  "displacement mm, load N; geometry from --thickness, --pin-radius); repeatable");
  cmd->callback([o, bins, points] {
    if (points->count() && (o->method != "fe" || o->fe.db.empty()))
      throw CLI::ValidationError(points->get_name(), "needs --method fe --db FILE --run ID");
    // The FE fit solves once per point and parameter: fewer, wider bins by default.
    if (o->method == "fe") o->fe.bins = bins->count() ? o->bins : o->fe.bins;
    run_fit(*o);
  });
}

}  // namespace

TOCD_CLI_COMMAND(fit, install_fit);

// The FE-in-the-loop branch of `tocdlab fit`: load-displacement data (a recorded run or a CSV)
// plus optional closed-form datasets, fitted jointly (docs/fe.md, "Inverse FE fit").
#include "fit_fe.hpp"

#include <cmath>
#include <iostream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "tocd/analysis/run_pin_data.hpp"
#include "tocd/core/error.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/sim/fe/inverse_fit.hpp"
#include "tocd/sim/material/fit.hpp"

namespace tocd::cli {
namespace {

namespace fe = tocd::sim::fe;
namespace mat = tocd::sim::material;

fe::FeModel geometry(const FitFeOptions& o, double thickness_mm) {
  fe::FeModel m = fe::FeModel::published_default();
  m.thickness_mm = thickness_mm;
  m.pin_radius_mm = o.pin_radius;
  m.kinematics = fe::parse_kinematics(o.kinematics);
  m.bottom = fe::parse_bottom(o.bottom);
  m.mesh_refinement = o.refine;
  return m;
}

// A CSV of (displacement mm, load N): the two-column reader, columns renamed.
fe::PinCompressionData pin_from_csv(const FitFeOptions& o, const std::string& path, double weight) {
  if (!(o.thickness > 0))
    throw tocd::ConfigError("a load-displacement CSV needs --thickness MM (the sample's)");
  const auto d = mat::read_stress_strain_csv(path);
  fe::PinCompressionData p;
  p.name = path;
  p.model = geometry(o, o.thickness);
  p.displacement_mm = d.strain;
  p.load_N = d.stress;
  p.weight = weight;
  return p;
}

void add_dataset(const FitFeOptions& o, const std::string& spec, std::vector<fe::PinCompressionData>& pins,
                 std::vector<fe::ClosedFormData>& closed) {
  const auto colon = spec.find(':');
  if (colon == std::string::npos)
    throw tocd::ConfigError(fmt::format("--dataset '{}': expected MODE:FILE[:WEIGHT]", spec));
  const std::string mode = spec.substr(0, colon);
  std::string file = spec.substr(colon + 1);
  double weight = 1;
  if (const auto c2 = file.rfind(':'); c2 != std::string::npos) {
    const std::string w = file.substr(c2 + 1);
    try {
      std::size_t used = 0;
      weight = std::stod(w, &used);
      if (used != w.size() || !(weight > 0)) throw std::invalid_argument(w);
    } catch (const std::exception&) {
      throw tocd::ConfigError(fmt::format("--dataset '{}': weight '{}' is not a positive number", spec, w));
    }
    file.resize(c2);
  }
  if (mode == "pin") {
    pins.push_back(pin_from_csv(o, file, weight));
    return;
  }
  const auto d = mat::read_stress_strain_csv(file);
  fe::ClosedFormData c;
  c.name = file;
  c.mode = mat::parse_loading_mode(mode);
  c.weight = weight;
  // Files hold nominal strain (stretch - 1) or the amount of shear, and nominal stress, signed.
  for (std::size_t k = 0; k < d.strain.size(); ++k)
    c.x.push_back(c.mode == mat::LoadingMode::simple_shear ? d.strain[k] : 1 + d.strain[k]);
  c.stress_MPa = d.stress;
  closed.push_back(std::move(c));
}

std::string interval(double lo, double hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) return "not identified";
  return fmt::format("[{:.6g}, {:.6g}]", lo, hi);
}

}  // namespace

void run_fit_fe(const FitFeOptions& o) {
  std::vector<fe::PinCompressionData> pins;
  std::vector<fe::ClosedFormData> closed;
  if (!o.db.empty()) {
    if (o.run <= 0) throw tocd::ConfigError("--db needs --run ID (see tocdlab runs --db FILE)");
    const auto points = tocd::analysis::parse_run_load_points(o.points);
    fe::PinCompressionData p = tocd::analysis::pin_data_from_run(tocd::db::Reader(o.db), o.run, points,
                                                                 o.pin_radius, o.bins, o.thickness);
    p.model = geometry(o, p.model.thickness_mm);
    p.weight = o.weight;
    std::cerr << fmt::format("run {}: {} {} load/displacement points, {} mm sample, pin radius {} mm\n",
                             o.run, p.load_N.size(), o.points, p.model.thickness_mm, o.pin_radius);
    pins.push_back(std::move(p));
  } else if (!o.csv.empty()) {
    pins.push_back(pin_from_csv(o, o.csv, o.weight));
  }
  for (const auto& s : o.datasets) add_dataset(o, s, pins, closed);

  fe::InverseFitOptions fo;
  fo.model = fe::parse_inverse_model(o.model);
  fo.fit_D = o.fit_D;
  // A least-squares fit needs more data points than free parameters; say which option
  // changes that instead of the solver's "6 data points for 6 parameters".
  std::size_t points = 0;
  for (const auto& p : pins) points += p.load_N.size();
  for (const auto& c : closed) points += c.x.size();
  const std::size_t parameters = fe::free_parameters(fo.model, o.fit_D);
  if (points <= parameters) {
    throw tocd::ConfigError(fmt::format(
        "--model {} has {} free parameters and the data give {} points; a fit needs more points than "
        "parameters: use --model scaled (one stiffness factor on the published law's shape){}",
        o.model, parameters, points,
        o.db.empty() ? std::string() : ", or --points loading (every reading of the loading curve)"));
  }
  fo.poisson_ratio = o.poisson;
  fo.confidence = o.confidence;
  fo.progress = [](const std::string& line) { std::cerr << "fit: " << line << '\n' << std::flush; };
  const fe::InverseFitResult r = fe::fit_material(pins, closed, fo);

  if (o.json) {
    nlohmann::json j = fe::to_json(r);
    j["method"] = "fe";
    if (!pins.empty())
      j["fe_model"] = {{"thickness_mm", pins[0].model.thickness_mm},
                       {"pin_radius_mm", pins[0].model.pin_radius_mm},
                       {"kinematics", fe::to_string(pins[0].model.kinematics)},
                       {"bottom", fe::to_string(pins[0].model.bottom)},
                       {"mesh_refinement", pins[0].model.mesh_refinement}};
    std::cout << j.dump(2) << '\n';
    return;
  }
  std::cout << fmt::format("{} law fitted through the FE ({} datasets, {} iterations, {} evaluations, {})\n",
                           fe::to_string(r.model), r.datasets.size(), r.iterations, r.evaluations,
                           r.converged ? r.stop_reason : "NOT converged: " + r.stop_reason);
  std::cout << fmt::format("  {:<7} {:>14} {:>12}  {:.0f} % interval\n", "", "value", "std error",
                           100 * r.confidence);
  for (std::size_t k = 0; k < r.names.size(); ++k)
    std::cout << fmt::format("  {:<7} {:>14.6g} {:>12.4g}  {}\n", r.names[k], r.values[k],
                             r.standard_errors[k], interval(r.interval_low[k], r.interval_high[k]));
  std::cout << fmt::format("  Ogden: mu [MPa] {}  alpha {}  D1 {:.6g} 1/MPa\n",
                           fmt::join(r.material.mu, ", "), fmt::join(r.material.alpha, ", "),
                           r.material.D.empty() ? 0.0 : r.material.D[0]);
  std::cout << fmt::format("  residual variance (relative) {:.4g}, i.e. {:.3g} % rms\n", r.residual_variance,
                           100 * std::sqrt(r.residual_variance));
  for (const auto& d : r.datasets) {
    std::cout << fmt::format("  {}: rms {:.3g} %, max {:.3g} %\n", d.name, 100 * d.rms_relative,
                             100 * d.max_abs_relative);
    for (std::size_t k = 0; k < d.x.size(); ++k)
      std::cout << fmt::format("    {:>9.4f} {:>12.5g} {:>12.5g} {:>+8.2f} %\n", d.x[k], d.measured[k],
                               d.fitted[k], 100 * (d.fitted[k] / d.measured[k] - 1));
  }
  std::cout << fmt::format(
      "  Drucker stability over stretch [{:.3g}, {:.3g}]: {}\n", r.stability.lambda_min,
      r.stability.lambda_max,
      r.stability.stable ? "stable"
                         : fmt::format("UNSTABLE ({}); stable in [{:.3g}, {:.3g}]", r.stability.first_failure,
                                       r.stable_lambda_min, r.stable_lambda_max));
}

}  // namespace tocd::cli

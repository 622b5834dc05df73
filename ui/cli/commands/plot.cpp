// `tocdlab plot`: figures as PNG or SVG files, drawn without a display (docs/plot.md).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "db_location_option.hpp"
#include "numeric_options.hpp"
#include "output_paths.hpp"
#include "tocd/acquisition/compare_table.hpp"
#include "tocd/core/error.hpp"
#include "tocd/core/text_file.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/plot/figures.hpp"
#include "tocd/plot/inputs.hpp"
#include "tocd/sim/material/fit.hpp"
#include "tocd/sim/material/ogden.hpp"

namespace cli = tocd::cli;
namespace plot = tocd::plot;

namespace {

struct PlotOptions {
  std::string output;
  plot::FigureSize size;
  // slices
  std::vector<std::string> slice_files;
  std::string slice_state;
  double decades = 6.0;
  // compare
  std::string db;
  std::int64_t run = 0;
  // fit
  std::string csv, fit_json, model = "ogden3";
  double poisson = 0.49;
  // study
  std::string study_json, column = "T_rel_b";
  // sensitivity
  std::string sensitivity_json;
  std::string title;
};

void wrote(const PlotOptions& o) {
  std::cerr << "tocdlab plot: wrote " << o.output << '\n';
}

// Standard error of each completed step's measured T: of the mean power over the recording
// window, divided by the baseline power (readings taken as independent), as the database's
// step_comparison view computes it. Keyed by step index; absent where it cannot be computed.
std::map<int, double> measured_T_se(const tocd::db::Reader& reader, std::int64_t run_id) {
  std::map<int, double> out;
  std::int64_t power = 0;
  for (const auto& ch : reader.channels(run_id))
    if (ch.name == "power") power = ch.id;
  const double baseline_W = reader.run(run_id).baseline_power_W;
  if (power == 0 || !(baseline_W > 0)) return out;
  for (const auto& s : reader.steps(run_id)) {
    const auto* p = s.stats_for(power);
    if (s.completed && p != nullptr && p->n > 1 && std::isfinite(p->std))
      out[s.index] = p->std / std::sqrt(static_cast<double>(p->n)) / baseline_W;
  }
  return out;
}

plot::CompareFigure compare_figure(const PlotOptions& o) {
  const tocd::db::Reader reader(o.db);
  const auto table = tocd::acquisition::compare_table(reader, o.run);
  const auto measured_se = measured_T_se(reader, o.run);
  plot::CompareFigure f;
  f.title = o.title.empty()
                ? fmt::format("run {} ({}): measured vs. predicted T", table.run_id, table.run_name)
                : o.title;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& l : table.lines) {
    plot::StepPoint s;
    s.step = l.index;
    s.displacement_mm = l.displacement_mm;
    s.measured_T = l.completed ? l.measured_T : nan;
    const auto se = measured_se.find(l.index);
    s.measured_T_se = l.completed && se != measured_se.end() ? se->second : nan;
    s.predicted_T = l.has_prediction ? l.predicted_T : nan;
    s.predicted_T_se = l.has_prediction ? l.predicted_T_stderr : nan;
    f.steps.push_back(s);
  }
  if (f.steps.empty()) throw tocd::ConfigError(fmt::format("run {} in {} has no steps to plot", o.run, o.db));
  return f;
}

// The Ogden form from `tocdlab fit --json` output.
tocd::sim::material::OgdenParameters ogden_from_fit_json(const std::string& path) {
  const auto text = tocd::read_text_file(path);
  if (!text) throw tocd::ConfigError("cannot read fit result '" + path + "'");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(*text);
  } catch (const nlohmann::json::parse_error& e) {
    throw tocd::ConfigError(path + ": not valid JSON (" + e.what() + ")");
  }
  const auto og = j.find("ogden");
  if (og == j.end() || !og->contains("mu_MPa") || !og->contains("alpha"))
    throw tocd::ConfigError(path + ": no \"ogden\" {mu_MPa, alpha} block (write it with tocdlab fit --json)");
  tocd::sim::material::OgdenParameters p;
  try {
    p.mu = og->at("mu_MPa").get<std::vector<double>>();
    p.alpha = og->at("alpha").get<std::vector<double>>();
  } catch (const nlohmann::json::exception& e) {
    throw tocd::ConfigError(path + ": \"ogden\" mu_MPa and alpha must be arrays of numbers (" + e.what() +
                            ")");
  }
  if (p.mu.empty() || p.mu.size() != p.alpha.size())
    throw tocd::ConfigError(path + ": \"ogden\" needs as many alpha as mu_MPa, at least one");
  return p;
}

plot::FitFigure fit_figure(const PlotOptions& o) {
  namespace mat = tocd::sim::material;
  const mat::StressStrainData d = mat::read_stress_strain_csv(o.csv);
  mat::OgdenParameters law;
  std::string label;
  if (!o.fit_json.empty()) {
    law = ogden_from_fit_json(o.fit_json);
    label = fmt::format("Ogden N = {} from {}", law.mu.size(), o.fit_json);
  } else {
    mat::FitOptions opt;
    opt.poisson_ratio = o.poisson;
    const auto r = mat::fit_uniaxial(d.strain, d.stress, mat::parse_fit_model(o.model), opt);
    if (!r.has_ogden_form)
      throw tocd::ConfigError("plot fit draws laws with an Ogden form: ogden1-3, neo-hookean, mooney-rivlin");
    law = r.ogden;
    label = fmt::format("{} fit (R\u00b2 {:.4f})", mat::to_string(r.model), r.r_squared);
  }
  plot::FitFigure f;
  f.title = o.title.empty() ? "stress-strain data and fitted law (uniaxial compression)" : o.title;
  f.strain = d.strain;
  f.stress_MPa = d.stress;
  f.curve_label = label;
  // Compression magnitudes, as `tocdlab fit` reads them: stretch 1 - strain, stress = -P.
  const double e_max = std::min(0.95, *std::max_element(d.strain.begin(), d.strain.end()));
  for (int k = 0; k <= 200; ++k) {
    const double e = e_max * k / 200.0;
    f.curve_strain.push_back(e);
    f.curve_stress_MPa.push_back(-mat::ogden_uniaxial_nominal_stress(law, 1.0 - e));
  }
  return f;
}

void add_common(CLI::App* cmd, PlotOptions& o) {
  cmd->add_option("-o,--output", o.output, "picture to write: FILE.png or FILE.svg")
      ->check(cli::output_file())
      ->required();
  cmd->add_option("--width", o.size.width, "width in pixels")
      ->check(cli::whole_in(std::int64_t{200}, std::int64_t{20000}))
      ->capture_default_str();
  cmd->add_option("--height", o.size.height, "height in pixels")
      ->check(cli::whole_in(std::int64_t{150}, std::int64_t{20000}))
      ->capture_default_str();
  cmd->add_option("--title", o.title, "title above the figure (a default names the input)");
}

void install_plot(CLI::App& root) {
  auto* cmd =
      root.add_subcommand("plot", "Draw figures as PNG or SVG files, no display needed (see docs/plot.md)");
  cmd->require_subcommand(1);
  auto o = std::make_shared<PlotOptions>();

  auto* slices =
      cmd->add_subcommand("slices", "Fluence slices (study --fluence-dir CSVs) on a log colour scale");
  add_common(slices, *o);
  slices->add_option("slices", o->slice_files, "slice CSV files, drawn side by side on one colour scale")
      ->required()
      ->check(CLI::ExistingFile);
  slices
      ->add_option("--state", o->slice_state,
                   "the JSON of the study or prediction that wrote the slices (study -o FILE.json, "
                   "predict --json): the title states its displacement and strain")
      ->check(CLI::ExistingFile);
  slices->add_option("--decades", o->decades, "decades of fluence the colour scale spans")
      ->check(cli::real_above(0.0, 30.0))
      ->capture_default_str();
  slices->callback([o] {
    plot::SliceFigure f;
    f.title = o->title;
    if (f.title.empty() && !o->slice_state.empty())
      f.title = plot::read_slice_state_title(o->slice_state, o->slice_files);
    f.decades = o->decades;
    for (const auto& path : o->slice_files) f.panels.push_back(plot::read_slice_csv(path));
    plot::write_figure(f, o->output, o->size);
    wrote(*o);
  });

  auto* compare = cmd->add_subcommand("compare", "Measured vs. predicted T per step of a recorded run");
  add_common(compare, *o);
  compare->add_option("--db", o->db, "measurement database file")->required();
  cli::add_run_id(compare, o->run);
  compare->callback([o] {
    plot::write_figure(compare_figure(*o), o->output, o->size);
    wrote(*o);
  });

  auto* fit = cmd->add_subcommand("fit", "Stress-strain data with the fitted Ogden law");
  add_common(fit, *o);
  fit->add_option("--csv", o->csv,
                  "two columns: strain, stress [MPa] (compression magnitudes, as tocdlab fit)")
      ->required();
  fit->add_option("--fit", o->fit_json,
                  "the law from `tocdlab fit --json` output (default: fit --model now)");
  fit->add_option("--model", o->model, "ogden1 | ogden2 | ogden3 | neo-hookean | mooney-rivlin")
      ->capture_default_str();
  fit->add_option("--poisson", o->poisson, "Poisson's ratio for the fit's D1")
      ->check(cli::real_above(-1.0, 0.5))
      ->capture_default_str();
  fit->callback([o] {
    plot::write_figure(fit_figure(*o), o->output, o->size);
    wrote(*o);
  });

  auto* study =
      cmd->add_subcommand("study", "A study's bar chart from its JSON (tocdlab study ... --json > FILE)");
  add_common(study, *o);
  // The study's JSON is an input, named like the other figures' inputs: --json means "print
  // JSON" everywhere else.
  study->add_option("study", o->study_json, "the study's JSON output (tocdlab study ... --json)")->required();
  study->add_option("--column", o->column, "what the bars show: T, T_rel_a, T_rel_b, side_loss, ...")
      ->capture_default_str();
  study->callback([o] {
    plot::BarFigure f = plot::read_study_bars(o->study_json, o->column);
    if (!o->title.empty()) f.title = o->title;
    plot::write_figure(f, o->output, o->size);
    wrote(*o);
  });

  auto* sensitivity = cmd->add_subcommand(
      "sensitivity", "The tornado of a sensitivity study (tocdlab study sensitivity --json > FILE)");
  add_common(sensitivity, *o);
  sensitivity->add_option("sensitivity", o->sensitivity_json, "the sensitivity study's JSON output")
      ->required();
  sensitivity->callback([o] {
    plot::TornadoFigure f = plot::read_sensitivity_tornado(o->sensitivity_json);
    if (!o->title.empty()) f.title = o->title;
    plot::write_figure(f, o->output, o->size);
    wrote(*o);
  });
}

}  // namespace

TOCD_CLI_COMMAND(plot, install_plot);

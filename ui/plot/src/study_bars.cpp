#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "input_file.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/inputs.hpp"

namespace tocd::plot {

namespace {

// A simulation as the study describes it: its number, what the compressed region is made of
// (or glass only, the baseline without skin) and its state, the pin's displacement and the
// nominal strain (displacement / thickness) it makes.
std::string simulation_label(const nlohmann::json& sim) {
  const int id = sim.value("sim", -1);
  const auto config = sim.find("config");
  const bool baseline = (config != sim.end() && config->is_object() && config->value("baseline", false)) ||
                        sim.value("optics", std::string()) == "glass only";
  if (baseline) return fmt::format("{}: glass only\nno skin", id);
  const double d = sim.value("displacement_mm", 0.0), h = sim.value("thickness_mm", 0.0);
  const double strain = sim.contains("strain") && sim["strain"].is_number() ? sim["strain"].get<double>()
                        : h > 0                                             ? d / h
                                                                            : NAN;
  // No-break spaces keep a number with its unit when the label wraps.
  const std::string state = d == 0.0 ? std::string("flat, 0\u00a0mm")
                            : std::isfinite(strain)
                                ? fmt::format("{:g}\u00a0mm, {:.0f}\u00a0%", d, 100.0 * strain)
                                : fmt::format("{:g}\u00a0mm", d);
  return fmt::format("{}: {}\n{}", id, sim.value("optics", std::string("?")), state);
}

// Words and units for the value axis; a column the study adds later keeps its key.
std::string axis_label(const std::string& column, const nlohmann::json& j) {
  auto ref = [&](const char* key) {
    return j.contains(key) && j[key].is_number_integer() ? j[key].get<int>() : -1;
  };
  if (column == "T") return "transmission T (fraction of the light)";
  if (column == "T_rel_a")
    return fmt::format("T relative to sim {} (T / T{})", ref("reference_a"), ref("reference_a"));
  if (column == "T_rel_b")
    return fmt::format("T relative to sim {} (T / T{})", ref("reference_b"), ref("reference_b"));
  if (column == "side_loss") return "side loss (fraction of the light, box sides)";
  if (column == "side_loss_slide") return "side loss through the slide's edges (fraction)";
  if (column == "reflectance") return "reflectance (fraction of the light)";
  if (column == "absorbed") return "absorbed (fraction of the light)";
  if (column == "specular") return "specular reflection (fraction of the light)";
  return column;
}

}  // namespace

BarFigure parse_study_bars(const std::string& json_text, const std::string& column,
                           const std::string& source) {
  nlohmann::json j = detail::parse_input_json(json_text, source);
  if (!j.is_object() || j.value("kind", "") != "tocdlab.study" || !j.contains("simulations") ||
      !j["simulations"].is_array())
    throw ConfigError(source +
                      ": not a study's JSON (expected \"kind\": \"tocdlab.study\" and \"simulations\"; "
                      "write one with tocdlab study ... --json FILE)");
  // A relative column holds T against its reference simulation; the study's table shows it
  // for the reference and the simulations run after it (the variants it is the reference of)
  // and "-" before it. The JSON fills it for every row once the reference has run: the rows
  // before the reference are left out here as in the table.
  int reference = -1;
  for (const auto& [col, key] : {std::pair{"T_rel_a", "reference_a"}, std::pair{"T_rel_b", "reference_b"}})
    if ((column == col || column == std::string(col) + "_se") && j.contains(key) &&
        j[key].is_number_integer())
      reference = j[key].get<int>();
  bool reference_seen = reference < 0;
  BarFigure out;
  out.y_label = axis_label(column, j);
  out.x_label = "simulation: compressed-region optics; pin displacement, nominal strain";
  for (const auto& sim : j["simulations"]) {
    const auto v = sim.find(column);
    if (v == sim.end()) {
      throw ConfigError(
          fmt::format("{}: simulation {} has no column '{}' (try T, T_rel_a, T_rel_b, side_loss)", source,
                      sim.value("sim", -1), column));
    }
    reference_seen = reference_seen || sim.value("sim", -1) == reference;
    if (!reference_seen) continue;
    if (!v->is_number()) continue;  // null: relative to a reference that is absent
    out.values.push_back(v->get<double>());
    double se = NAN;
    for (const std::string& key : {column + "_se", column + "_stderr"})
      if (sim.contains(key) && sim[key].is_number()) se = sim[key].get<double>();
    out.errors.push_back(se);
    out.labels.push_back(simulation_label(sim));
  }
  if (out.values.empty())
    throw ConfigError(source + ": no simulation has a value in column '" + column + "'");
  // The title names the reference of a relative column by the study's own description of it.
  std::string of =
      column == "T" ? std::string("transmission T") : out.y_label.substr(0, out.y_label.find(" ("));
  if (reference >= 0)
    for (const auto& sim : j["simulations"])
      if (sim.value("sim", -1) == reference) {
        std::string d = simulation_label(sim);
        d.replace(d.find('\n'), 1, ", ");
        for (auto at = d.find("\u00a0"); at != std::string::npos; at = d.find("\u00a0"))
          d.replace(at, 2, " ");
        of = fmt::format("T / T{} (sim {})", reference, d);
      }
  out.title = fmt::format("{} per simulation (error bars: \u00b11 standard error)", of);
  return out;
}

BarFigure read_study_bars(const std::filesystem::path& json_path, const std::string& column) {
  return parse_study_bars(detail::read_input_file(json_path, "study JSON"), column, json_path.string());
}

}  // namespace tocd::plot

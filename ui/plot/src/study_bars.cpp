#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tocd/core/error.hpp"
#include "tocd/plot/inputs.hpp"

namespace tocd::plot {

BarFigure parse_study_bars(const std::string& json_text, const std::string& column,
                           const std::string& source) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(json_text);
  } catch (const nlohmann::json::parse_error& e) {
    throw ConfigError(source + ": not valid JSON (" + e.what() + ")");
  }
  if (!j.is_object() || j.value("kind", "") != "tocdlab.study" || !j.contains("simulations") ||
      !j["simulations"].is_array())
    throw ConfigError(source +
                      ": not a study's JSON (expected \"kind\": \"tocdlab.study\" and \"simulations\"; "
                      "write one with tocdlab study ... --json FILE)");
  BarFigure out;
  out.y_label = column == "T" ? "transmission T" : column;
  for (const auto& sim : j["simulations"]) {
    const auto v = sim.find(column);
    if (v == sim.end()) {
      throw ConfigError(
          fmt::format("{}: simulation {} has no column '{}' (try T, T_rel_a, T_rel_b, side_loss)", source,
                      sim.value("sim", -1), column));
    }
    if (!v->is_number()) continue;  // null: relative to a reference that is absent
    out.values.push_back(v->get<double>());
    double se = NAN;
    for (const std::string& key : {column + "_se", column + "_stderr"})
      if (sim.contains(key) && sim[key].is_number()) se = sim[key].get<double>();
    out.errors.push_back(se);
    const double d = sim.value("displacement_mm", 0.0);
    out.labels.push_back(d == 0.0 ? fmt::format("{}: glass", sim.value("sim", -1))
                                  : fmt::format("{}: {:.2g} mm {}", sim.value("sim", -1), d,
                                                sim.value("optics", std::string())));
  }
  if (out.values.empty())
    throw ConfigError(source + ": no simulation has a value in column '" + column + "'");
  out.title = fmt::format("study: {} per simulation", column);
  return out;
}

BarFigure read_study_bars(const std::filesystem::path& json_path, const std::string& column) {
  std::ifstream in(json_path, std::ios::binary);
  if (!in || std::filesystem::is_directory(json_path))
    throw ConfigError("cannot read study JSON '" + json_path.string() + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_study_bars(text.str(), column, json_path.string());
}

}  // namespace tocd::plot

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tocd/core/error.hpp"
#include "tocd/plot/inputs.hpp"

namespace tocd::plot {

TornadoFigure parse_sensitivity_tornado(const std::string& json_text, const std::string& source) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(json_text);
  } catch (const nlohmann::json::parse_error& e) {
    throw ConfigError(source + ": not valid JSON (" + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("tornado") || !j["tornado"].is_array() || !j.contains("base"))
    throw ConfigError(source +
                      ": not a sensitivity study's JSON (expected \"base\" and \"tornado\"; write one with "
                      "tocdlab study sensitivity --json > FILE)");
  TornadoFigure out;
  out.x_label = "dT = T(variant) - T(base)";
  for (const auto& row : j["tornado"]) {
    const auto dT = row.find("dT");
    if (dT == row.end() || !dT->is_number())
      throw ConfigError(fmt::format("{}: a tornado row has no number dT", source));
    out.labels.push_back(
        fmt::format("{}: {}", row.value("factor", std::string("?")), row.value("label", std::string("?"))));
    out.values.push_back(dT->get<double>());
    const auto se = row.find("dT_se");
    out.errors.push_back(se != row.end() && se->is_number() ? se->get<double>() : NAN);
  }
  if (out.values.empty()) throw ConfigError(source + ": the tornado has no rows");
  const auto& base = j["base"];
  out.title = base.contains("T") && base["T"].is_number()
                  ? fmt::format("sensitivity of T = {:.4f} to the modelling choices", base["T"].get<double>())
                  : std::string("sensitivity of T to the modelling choices");
  return out;
}

TornadoFigure read_sensitivity_tornado(const std::filesystem::path& json_path) {
  std::ifstream in(json_path, std::ios::binary);
  if (!in || std::filesystem::is_directory(json_path))
    throw ConfigError("cannot read sensitivity JSON '" + json_path.string() + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_sensitivity_tornado(text.str(), json_path.string());
}

}  // namespace tocd::plot

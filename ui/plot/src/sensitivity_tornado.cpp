#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "input_file.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/inputs.hpp"

namespace tocd::plot {

TornadoFigure parse_sensitivity_tornado(const std::string& json_text, const std::string& source) {
  nlohmann::json j = detail::parse_input_json(json_text, source);
  if (!j.is_object() || !j.contains("tornado") || !j["tornado"].is_array() || !j.contains("base"))
    throw ConfigError(source +
                      ": not a sensitivity study's JSON (expected \"base\" and \"tornado\"; write one with "
                      "tocdlab study sensitivity --json > FILE)");
  TornadoFigure out;
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
  // The title names the quantity and the step the variants change: T of the base prediction
  // at its displacement into its skin thickness (the nominal strain d / h), as its config says.
  const auto& base = j["base"];
  std::string step = "one step";
  if (base.contains("config") && base["config"].is_object()) {
    const auto& c = base["config"];
    const double d = c.value("displacement_mm", NAN), h = c.value("thickness_mm", NAN);
    if (std::isfinite(d) && std::isfinite(h) && h > 0)
      step = fmt::format("the {:g} mm step ({:g} mm skin, {:.0f} % strain)", d, h, 100.0 * d / h);
  }
  std::string T = "T";
  if (base.contains("T") && base["T"].is_number())
    T = base.contains("T_se") && base["T_se"].is_number()
            ? fmt::format("T = {:.4f} \u00b1 {:.4f}", base["T"].get<double>(), base["T_se"].get<double>())
            : fmt::format("T = {:.4f}", base["T"].get<double>());
  out.title = fmt::format("sensitivity of the transmission at {}: base {}", step, T);
  out.x_label = "dT = T(variant) - T(base)  (error bars: \u00b11 standard error)";
  return out;
}

TornadoFigure read_sensitivity_tornado(const std::filesystem::path& json_path) {
  return parse_sensitivity_tornado(detail::read_input_file(json_path, "sensitivity JSON"),
                                   json_path.string());
}

}  // namespace tocd::plot

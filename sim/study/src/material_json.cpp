#include "material_json.hpp"

#include <fmt/format.h>

#include "json_keys.hpp"
#include "tocd/core/error.hpp"

namespace tocd::sim::study {

nlohmann::json material_to_json(const tocd::sim::material::OgdenParameters& m) {
  return {{"mu", m.mu}, {"alpha", m.alpha}, {"D", m.D}};
}

tocd::sim::material::OgdenParameters material_from_json(const nlohmann::json& j) {
  tocd::sim::material::OgdenParameters m;
  require_known_keys(j, {"mu", "alpha", "D"}, "material in config");
  try {
    m.mu = j.at("mu").get<std::vector<double>>();
    m.alpha = j.at("alpha").get<std::vector<double>>();
    m.D = j.value("D", std::vector<double>{});
  } catch (const nlohmann::json::exception& e) {
    throw tocd::ConfigError(
        fmt::format("material in config: expected mu, alpha (and D) number lists ({})", e.what()));
  }
  m.validate();
  return m;
}

}  // namespace tocd::sim::study

#pragma once

#include <nlohmann/json.hpp>

#include "tocd/sim/material/ogden.hpp"

namespace tocd::sim::study {

/// {"mu": [...], "alpha": [...], "D": [...]} (MPa, -, 1/MPa).
nlohmann::json material_to_json(const tocd::sim::material::OgdenParameters& m);
/// Reads it back; throws tocd::ConfigError on missing or non-numeric entries, and the
/// material's own MaterialError on invalid parameters.
tocd::sim::material::OgdenParameters material_from_json(const nlohmann::json& j);

}  // namespace tocd::sim::study

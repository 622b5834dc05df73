#include "tocd/sim/mc/optics.hpp"

#include <cmath>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "tocd/core/text_file.hpp"

namespace tocd::sim::mc {

void validate(const Optics& optics, const std::string& where) {
  if (optics.regions.empty()) throw OpticsError(fmt::format("{}: no regions defined", where));
  if (optics.ambient_n != 0.0 && !(optics.ambient_n > 0.0 && std::isfinite(optics.ambient_n))) {
    throw OpticsError(fmt::format("{}: ambient_n = {} must be > 0", where, optics.ambient_n));
  }
  for (const auto& [id, r] : optics.regions) {
    // `region = id`: clang 14 cannot capture a structured binding by reference.
    auto bad = [&, region = id](const char* key, double v, const char* rule) {
      throw OpticsError(fmt::format("{}: region {}: {} = {} {}", where, region, key, v, rule));
    };
    if (!(r.mu_a_per_mm >= 0.0) || !std::isfinite(r.mu_a_per_mm))
      bad("mu_a", r.mu_a_per_mm, "must be finite and >= 0");
    if (!(r.mu_s_per_mm >= 0.0) || !std::isfinite(r.mu_s_per_mm))
      bad("mu_s", r.mu_s_per_mm, "must be finite and >= 0");
    if (!(r.g > -1.0 && r.g <= 1.0)) bad("g", r.g, "must lie in (-1, 1] (1 = no deflection)");
    if (!(r.n > 0.0) || !std::isfinite(r.n)) bad("n", r.n, "must be finite and > 0");
  }
}

Optics parse_optics_toml(const std::string& text, const std::string& name) {
  toml::table doc;
  try {
    doc = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    const auto& src = e.source();
    throw OpticsError(fmt::format("{}:{}:{}: {}", name, src.begin.line, src.begin.column, e.description()));
  }
  Optics optics;
  if (const auto* amb = doc.get("ambient_n")) {
    const auto v = amb->value<double>();
    if (!v) throw OpticsError(fmt::format("{}: ambient_n must be a number", name));
    optics.ambient_n = *v;
  }
  const auto* regions = doc["region"].as_table();
  if (!regions) throw OpticsError(fmt::format("{}: no [region.<id>] tables", name));
  for (const auto& [key, node] : *regions) {
    const std::string id_text(key.str());
    char* end = nullptr;
    const long id = std::strtol(id_text.c_str(), &end, 10);
    if (id_text.empty() || *end != '\0') {
      throw OpticsError(fmt::format("{}: [region.{}]: the region id must be an integer", name, id_text));
    }
    const auto* tbl = node.as_table();
    if (!tbl) throw OpticsError(fmt::format("{}: region.{} must be a table", name, id_text));
    RegionOptics r;
    auto number = [&](const char* k) {
      const auto* n = tbl->get(k);
      if (!n) throw OpticsError(fmt::format("{}: [region.{}] is missing '{}'", name, id_text, k));
      const auto v = n->value<double>();
      if (!v) throw OpticsError(fmt::format("{}: [region.{}] '{}' must be a number", name, id_text, k));
      return *v;
    };
    r.mu_a_per_mm = number("mu_a");
    r.mu_s_per_mm = number("mu_s");
    r.g = number("g");
    r.n = number("n");
    if (const auto* nm = tbl->get("name")) r.name = nm->value_or(std::string{});
    for (const auto& [k, v] : *tbl) {
      const auto ks = k.str();
      if (ks != "mu_a" && ks != "mu_s" && ks != "g" && ks != "n" && ks != "name") {
        throw OpticsError(fmt::format(
            "{}: [region.{}] has unknown key '{}' (expected mu_a, mu_s, g, n, name)", name, id_text, ks));
      }
    }
    optics.regions[static_cast<std::int32_t>(id)] = r;
  }
  validate(optics, name);
  return optics;
}

Optics load_optics_toml(const std::filesystem::path& path) {
  const auto text = read_text_file(path);
  if (!text) throw OpticsError(fmt::format("cannot open optics file {}", path.string()));
  return parse_optics_toml(*text, path.string());
}

}  // namespace tocd::sim::mc

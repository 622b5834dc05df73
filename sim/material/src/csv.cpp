#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "tocd/core/text_file.hpp"
#include "tocd/sim/material/fit.hpp"

namespace tocd::sim::material {

namespace {
bool parse_double(const std::string& s, double& v) {
  std::size_t used = 0;
  try {
    v = std::stod(s, &used);
  } catch (...) {
    return false;
  }
  return used == s.size();
}
}  // namespace

StressStrainData parse_stress_strain_csv(const std::string& text, const std::string& source_name) {
  StressStrainData d;
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  bool seen_data = false;
  while (std::getline(in, line)) {
    ++lineno;
    if (auto h = line.find('#'); h != std::string::npos) line.erase(h);
    for (char& c : line)
      if (c == ',' || c == ';' || c == '\t' || c == '\r') c = ' ';
    std::istringstream ls(line);
    std::vector<std::string> fields;
    for (std::string f; ls >> f;) fields.push_back(f);
    if (fields.empty()) continue;
    double e = 0, s = 0;
    const bool numeric = fields.size() >= 2 && parse_double(fields[0], e) && parse_double(fields[1], s);
    if (!numeric) {
      if (!seen_data && d.strain.empty()) {  // one header line is allowed
        seen_data = true;
        continue;
      }
      throw MaterialError(fmt::format("{} line {}: expected two numbers (strain, stress), found '{}'",
                                      source_name, lineno, line));
    }
    if (fields.size() > 2)
      throw MaterialError(fmt::format("{} line {}: expected two columns (strain, stress), found {}",
                                      source_name, lineno, fields.size()));
    if (!std::isfinite(e) || !std::isfinite(s))
      throw MaterialError(fmt::format("{} line {}: value is not finite", source_name, lineno));
    seen_data = true;
    d.strain.push_back(e);
    d.stress.push_back(s);
  }
  if (d.strain.empty()) throw MaterialError(fmt::format("{}: no strain-stress rows found", source_name));
  return d;
}

StressStrainData read_stress_strain_csv(const std::filesystem::path& path) {
  const auto text = read_text_file(path);
  if (!text) throw MaterialError(fmt::format("cannot open stress-strain file {}", path.string()));
  return parse_stress_strain_csv(*text, path.string());
}

}  // namespace tocd::sim::material

#include "output_naming.hpp"

#include <algorithm>
#include <iostream>
#include <string_view>
#include <thread>

#include "progress.hpp"

namespace tocd::cli {

namespace {

constexpr std::string_view kStderrSuffix = "_stderr";

bool is_estimate(const nlohmann::json& j) {
  return j.is_object() && j.size() == 2 && j.contains("mean") && j.contains("se");
}

std::string renamed(const std::string& key) {
  if (key.size() > kStderrSuffix.size() && key.ends_with(kStderrSuffix))
    return key.substr(0, key.size() - kStderrSuffix.size()) + "_se";
  return key;
}

nlohmann::json step_element(nlohmann::json element) {
  if (element.is_object() && element.contains("index") && element["index"].is_number_integer() &&
      !element.contains("step")) {
    nlohmann::json out = nlohmann::json::object();
    out["step"] = element["index"].get<long long>() + 1;
    for (auto& [k, v] : element.items())
      if (k != "index") out[k] = std::move(v);
    return out;
  }
  return element;
}

}  // namespace

nlohmann::json to_naming_table(nlohmann::json j) {
  if (j.is_array()) {
    for (auto& e : j) e = to_naming_table(std::move(e));
    return j;
  }
  if (!j.is_object()) return j;
  nlohmann::json out = nlohmann::json::object();
  for (auto& [key, value] : j.items()) {
    const std::string name = renamed(key);
    if (is_estimate(value)) {
      out[name] = value["mean"];
      out[name + "_se"] = value["se"];
      continue;
    }
    if (name == "steps" && value.is_array())
      for (auto& e : value) e = step_element(std::move(e));
    out[name] = to_naming_table(std::move(value));
  }
  return out;
}

std::string to_naming_table_csv(const std::string& csv) {
  std::string lf;
  lf.reserve(csv.size());
  for (std::size_t i = 0; i < csv.size(); ++i)
    if (!(csv[i] == '\r' && i + 1 < csv.size() && csv[i + 1] == '\n')) lf += csv[i];
  const std::size_t header_end = std::min(lf.find('\n'), lf.size());
  std::string header = lf.substr(0, header_end);
  for (std::size_t pos; (pos = header.find(kStderrSuffix)) != std::string::npos;)
    header.replace(pos, kStderrSuffix.size(), "_se");
  return header + lf.substr(header_end);
}

}  // namespace tocd::cli

namespace tocd::cli {

void print_json(const nlohmann::json& j) {
  std::cout << to_naming_table(j).dump(2) << '\n' << std::flush;
}

void announce_file(const std::string& what, const std::string& path) {
  if (!progress_quiet()) std::cerr << "wrote " << what << ": " << path << '\n';
}

int resolve_threads(int requested) {
  return requested > 0 ? requested : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace tocd::cli

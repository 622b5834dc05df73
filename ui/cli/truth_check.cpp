// The identified sample against the simulated sample's truth (truth_check.hpp).
#include "truth_check.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "identify_report.hpp"
#include "tocd/analysis/run_history.hpp"

namespace tocd::cli {

namespace {

namespace an = tocd::analysis;

// The identification calls the sample's single relaxation term g1 and tau1_s; every other
// truth field keeps its name there.
std::string identified_name(const std::string& truth_field) {
  if (truth_field == "relaxation_fraction") return "g1";
  if (truth_field == "relaxation_time_s") return "tau1_s";
  return truth_field;
}

std::vector<const an::ParameterReport*> reports(const an::SampleIdentification& id) {
  std::vector<const an::ParameterReport*> out{&id.mechanics.report};
  if (id.clearing) out.push_back(&id.clearing->report);
  if (id.optics) out.push_back(&id.optics->report);
  return out;
}

std::optional<an::IdentifiedParameter> find(const an::SampleIdentification& id, const std::string& name) {
  for (const auto* r : reports(id))
    for (const auto& p : r->parameters)
      if (p.name == name) return p;
  return std::nullopt;
}

int prony_terms(const an::SampleIdentification& id) {
  const auto& ps = id.mechanics.report.parameters;
  return static_cast<int>(std::count_if(
      ps.begin(), ps.end(), [](const an::IdentifiedParameter& p) { return p.name.rfind("tau", 0) == 0; }));
}

// The table's relative error at `d`: linear between its points, its end values beyond them.
double relative_error_at(const mocks::SimTissueTable& t, double d) {
  std::vector<double> rel(t.transmission.size());
  for (std::size_t k = 0; k < rel.size(); ++k)
    rel[k] = t.transmission[k] > 0 ? t.transmission_stderr[k] / t.transmission[k] : std::nan("");
  return an::interpolate(t.displacement_mm, rel, d);
}

}  // namespace

int TruthCheck::determined() const {
  return static_cast<int>(
      std::count_if(parameters.begin(), parameters.end(), [](const Parameter& p) { return p.determined; }));
}

int TruthCheck::covered() const {
  return static_cast<int>(std::count_if(parameters.begin(), parameters.end(),
                                        [](const Parameter& p) { return p.determined && p.covered; }));
}

int TruthCheck::steps_within(double multiple) const {
  return static_cast<int>(std::count_if(steps.begin(), steps.end(),
                                        [multiple](const Step& s) { return std::abs(s.z) <= multiple; }));
}

TruthCheck check_against_truth(const an::SampleIdentification& id, const mocks::SampleTruth& truth,
                               const mocks::SimTissueTable& table) {
  TruthCheck out;
  const bool one_term = prony_terms(id) == 1;
  for (const auto& field : mocks::kSampleTruthFields) {
    const std::string name = identified_name(field.name);
    if (!one_term && (name == "g1" || name == "tau1_s")) continue;
    const auto p = find(id, name);
    if (!p) continue;
    TruthCheck::Parameter c;
    c.name = name;
    c.truth = truth.*field.value;
    c.value = p->value;
    c.lo = p->lo;
    c.hi = p->hi;
    c.determined = p->determined;
    c.covered = std::isfinite(p->lo) && std::isfinite(p->hi) && p->lo <= c.truth && c.truth <= p->hi;
    out.parameters.push_back(c);
  }
  if (!id.optics) return out;
  for (const auto& s : id.optics->steps) {
    TruthCheck::Step c;
    c.step = s.step_index + 1;
    c.displacement_mm = s.displacement_mm;
    c.measured_T = s.measured_T;
    c.measured_se = s.measured_T_se;
    c.sample_se = s.measured_T * relative_error_at(table, s.displacement_mm);
    c.predicted_T = s.predicted_T;
    c.predicted_se = s.predicted_T_se;
    c.combined_se = std::sqrt(c.measured_se * c.measured_se + c.sample_se * c.sample_se +
                              c.predicted_se * c.predicted_se);
    c.z = (c.predicted_T - c.measured_T) / c.combined_se;
    out.steps.push_back(c);
  }
  return out;
}

void print_truth_check(std::ostream& out, const TruthCheck& check) {
  out << "Against the simulated sample's truth (the demo knows it; the identification did not read it):\n";
  out << fmt::format("  {:<24} {:>11} {:>11}  {:<26} {}\n", "parameter", "truth", "identified",
                     "95 % interval", "covers the truth");
  for (const auto& p : check.parameters)
    out << fmt::format("  {:<24} {:>11.5g} {:>11.5g}  {:<26} {}\n", p.name, p.truth, p.value,
                       interval_text(p.lo, p.hi),
                       !p.determined ? "(not determined)"
                       : p.covered   ? "yes"
                                     : "NO");
  out << fmt::format("  {} of {} determined intervals cover the truth\n", check.covered(),
                     check.determined());
  if (check.steps.empty()) return;
  out << fmt::format("  {:>4} {:>8} {:>11} {:>10} {:>10} {:>12} {:>10} {:>11} {:>6}\n", "step", "d_mm",
                     "measured_T", "window_se", "sample_se", "identified_T", "mc_se", "combined_se", "z");
  for (const auto& s : check.steps)
    out << fmt::format(
        "  {:>4} {:>8.3f} {:>11.5f} {:>10.5f} {:>10.5f} {:>12.5f} {:>10.5f} {:>11.5f} {:>+6.2f}\n", s.step,
        s.displacement_mm, s.measured_T, s.measured_se, s.sample_se, s.predicted_T, s.predicted_se,
        s.combined_se, s.z);
  out << fmt::format(
      "  z = (identified - measured) / combined_se, with combined_se the window's scatter, the simulated "
      "sample's own Monte Carlo error and the re-prediction's in quadrature: {} of {} steps within 1, "
      "{} within 2 (for errors that are right, about 68 % and 95 %)\n",
      check.steps_within(1.0), check.steps.size(), check.steps_within(2.0));
}

nlohmann::json to_json(const TruthCheck& check) {
  auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  nlohmann::json parameters = nlohmann::json::array();
  for (const auto& p : check.parameters)
    parameters.push_back({{"name", p.name},
                          {"truth", p.truth},
                          {"identified", p.value},
                          {"interval", {finite(p.lo), finite(p.hi)}},
                          {"determined", p.determined},
                          {"covers_truth", p.determined ? nlohmann::json(p.covered) : nlohmann::json()}});
  nlohmann::json steps = nlohmann::json::array();
  for (const auto& s : check.steps)
    steps.push_back({{"step", s.step},
                     {"displacement_mm", s.displacement_mm},
                     {"measured_T", s.measured_T},
                     {"measured_T_se", finite(s.measured_se)},
                     {"sample_T_se", finite(s.sample_se)},
                     {"identified_T", s.predicted_T},
                     {"identified_T_se", finite(s.predicted_se)},
                     {"combined_se", finite(s.combined_se)},
                     {"z", finite(s.z)}});
  return {{"parameters", parameters},
          {"determined", check.determined()},
          {"determined_covering_truth", check.covered()},
          {"steps", steps},
          {"steps_within_1_se", check.steps_within(1.0)},
          {"steps_within_2_se", check.steps_within(2.0)}};
}

}  // namespace tocd::cli

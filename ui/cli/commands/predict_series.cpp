#include "predict_series.hpp"

#include <filesystem>
#include <iostream>
#include <map>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tocd/core/error.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/sim/parallel/team.hpp"
#include "tocd/sim/study/predictor.hpp"
#include "tocd/sim/vtk/pvd.hpp"

namespace tocd::cli {

namespace st = sim::study;

namespace {

st::PredictionRequest stored_step(const db::PredictionRecord& p) {
  const auto j = nlohmann::json::parse(p.config_json, nullptr, false);
  if (j.is_discarded())
    throw ConfigError(
        fmt::format("prediction {} (step {}): its stored config is not JSON", p.id, p.step_index + 1));
  try {
    return st::config_document_from_json(j).step;
  } catch (const ConfigError& e) {
    throw ConfigError(fmt::format("prediction {} (step {}): {}", p.id, p.step_index + 1, e.what()));
  }
}

}  // namespace

void predict_run_series(const RunSeriesOptions& o) {
  std::map<int, db::PredictionRecord> latest;  // by step; predictions come ordered by (step, id)
  {
    const db::Reader reader(o.db);
    reader.run(o.run);  // unknown run: DatabaseError before anything is written
    for (auto& p : reader.predictions(o.run)) latest[p.step_index] = std::move(p);
  }
  if (latest.empty())
    throw ConfigError(
        fmt::format("run {} has no stored predictions: nothing to re-run (see tocdlab compare)", o.run));
  std::vector<std::pair<int, st::PredictionRequest>> steps;
  for (const auto& [index, p] : latest) steps.emplace_back(index, stored_step(p));  // all parse, or none runs

  std::filesystem::create_directories(o.output_dir);
  st::Predictor predictor(1, &sim::parallel::world());
  std::vector<sim::vtk::PvdEntry> entries;
  nlohmann::json rows = nlohmann::json::array();
  for (auto& [index, r] : steps) {
    r.threads = o.threads;
    r.fluence_dir = o.output_dir;
    r.fluence_stem = fmt::format("step{:03d}", index + 1);
    r.vtu_format = o.format;
    std::cerr << fmt::format("step {} of run {}: d = {} mm, {} photons ...\n", index + 1, o.run,
                             r.displacement_mm, r.photons);
    const st::Prediction p = predictor.predict(r);
    const std::string vtu = p.fluence["vtu"].get<std::string>();
    entries.push_back({static_cast<double>(index + 1), vtu});
    rows.push_back({{"step", index + 1},
                    {"displacement_mm", r.displacement_mm},
                    {"T_step", p.T},
                    {"T_step_se", p.T_stderr},
                    {"vtu", vtu}});
  }
  const auto pvd = std::filesystem::path(o.output_dir) / "run.pvd";
  sim::vtk::write_pvd(entries, pvd);
  if (o.json) {
    std::cout << nlohmann::json{{"run", o.run}, {"pvd", pvd.string()}, {"steps", rows}}.dump(2) << '\n';
    return;
  }
  std::cout << fmt::format("{:>4}  {:>15}  {:>9}  {:>9}  {}\n", "step", "displacement_mm", "T_step",
                           "T_step_se", "vtu");
  for (const auto& row : rows)
    std::cout << fmt::format("{:>4}  {:>15}  {:>9.6f}  {:>9.6f}  {}\n", row["step"].get<int>(),
                             row["displacement_mm"].get<double>(), row["T_step"].get<double>(),
                             row["T_step_se"].get<double>(), row["vtu"].get<std::string>());
  std::cout << "series: " << pvd.string() << '\n';
}

}  // namespace tocd::cli

// A recorded run's sample, mechanics and clearing (identify_sample.hpp).
#include "tocd/analysis/identify_sample.hpp"

#include <chrono>

#include <fmt/format.h>

#include "tocd/analysis/run_history.hpp"

namespace tocd::analysis {

SampleIdentification identify_sample(const db::Reader& reader, std::int64_t run_id,
                                     const SampleIdentificationOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const RunHistory history = read_run_history(reader, run_id);
  SampleIdentification id;
  id.run_id = run_id;
  id.thickness_mm = history.thickness_mm;
  MechanicsOptions mo = options.mechanics;
  if (!mo.progress) mo.progress = options.progress;
  id.mechanics = identify_mechanics(history, mo);
  if (options.clearing && !history.transmission.empty()) {
    if (options.progress)
      options.progress("clearing time course from the transmission readings in the holds");
    id.clearing = identify_clearing(history);
  }
  if (id.clearing && options.optics && id.clearing->displacement_mm.size() < kOpticalParameters) {
    id.optics_not_identified = fmt::format("{} held displacement(s) for {} optical parameters",
                                           id.clearing->displacement_mm.size(), kOpticalParameters);
  } else if (id.clearing && options.optics) {
    OpticsOptions oo = options.monte_carlo;
    if (!oo.progress) oo.progress = options.progress;
    oo.pin_radius_mm = mo.pin_radius_mm;
    id.optics = identify_optics(history, *id.clearing, id.mechanics.report.at("stiffness_scale").value, oo);
  }
  id.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return id;
}

nlohmann::json to_json(const SampleIdentification& id) {
  nlohmann::json j = {{"run", id.run_id},
                      {"thickness_mm", id.thickness_mm},
                      {"mechanics", to_json(id.mechanics)},
                      {"seconds", id.seconds}};
  j["clearing"] = id.clearing ? to_json(*id.clearing) : nlohmann::json();
  j["optics"] = id.optics ? to_json(*id.optics) : nlohmann::json();
  if (!id.optics_not_identified.empty()) j["optics_not_identified"] = id.optics_not_identified;
  return j;
}

}  // namespace tocd::analysis

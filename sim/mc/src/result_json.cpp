#include "tocd/sim/mc/output.hpp"

namespace tocd::sim::mc {
namespace {
nlohmann::json estimate(const Estimate& e) {
  return {{"mean", e.mean}, {"se", e.se}};
}
}  // namespace

nlohmann::json to_json(const Result& r) {
  nlohmann::json j;
  j["photons"] = r.photons;
  j["seed"] = r.seed;
  j["threads"] = r.threads;
  j["ranks"] = r.ranks;
  j["batches"] = r.batches;
  j["cancelled"] = r.cancelled;
  j["transmittance"] = estimate(r.transmittance);
  j["reflectance"] = estimate(r.reflectance);
  j["side_loss"] = estimate(r.side_loss);
  j["absorbed"] = estimate(r.absorbed);
  j["specular"] = estimate(r.specular);
  j["roulette_balance"] = estimate(r.roulette_balance);
  j["missed"] = estimate(r.missed);
  j["lost"] = estimate(r.lost);
  auto& markers = j["exit_by_marker"] = nlohmann::json::object();
  for (const auto& [m, e] : r.exit_by_marker) markers[std::to_string(m)] = estimate(e);
  auto& regions = j["absorbed_by_region"] = nlohmann::json::object();
  for (const auto& [id, e] : r.absorbed_by_region) regions[std::to_string(id)] = estimate(e);
  if (!r.transmittance_derivatives.empty()) {  // only when the run computed them
    auto& d = j["transmittance_derivatives"] = nlohmann::json::object();
    for (const auto& [id, e] : r.transmittance_derivatives)
      d[std::to_string(id)] = {{"dT_dmu_a_mm", estimate(e.dT_dmu_a)}, {"dT_dmu_s_mm", estimate(e.dT_dmu_s)}};
  }
  j["energy_balance_error"] = r.energy_balance_error;
  j["events"] = r.events;
  j["face_hits"] = r.face_hits;
  j["seconds"] = r.seconds;
  j["photons_per_second"] = r.photons_per_second;
  j["events_per_second"] = r.events_per_second;
  return j;
}

}  // namespace tocd::sim::mc

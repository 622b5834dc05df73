// `tocdlab predict --optics water`: the transmission of one step as a function of time into
// its hold, from the biphasic (poroelastic) FE and water-content optics.
#include "predict_water.hpp"

#include <iostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "output_naming.hpp"
#include "progress.hpp"

namespace tocd::cli {

void run_predict_water(PredictWaterOptions o) {
  auto& r = o.request;
  r.times_s = o.times_s.empty() ? std::vector<double>{0, o.hold_s / 6, o.hold_s / 2, o.hold_s} : o.times_s;
  sim::study::validate(r);  // before the progress line: a bad request is an error, not a job
  ProgressBar bar("predict: water time course (FE + mesh + Monte Carlo per time point)", r.times_s.size(),
                  "time points");
  r.progress = [&bar](std::size_t done, std::size_t) { bar.update(done); };
  const auto points = sim::study::predict_water_time_course(r);
  bar.finish();
  if (o.json) {
    nlohmann::json pts = nlohmann::json::array();
    for (const auto& p : points) pts.push_back(sim::study::to_json(p));
    print_json({{"optics", "water"},
                {"config",
                 {{"displacement_mm", r.displacement_mm},
                  {"thickness_mm", r.thickness_mm},
                  {"ramp_s", r.ramp_s},
                  {"drained_poisson", r.drained_poisson},
                  {"k0_mm4_per_Ns", r.permeability.k0_mm4_per_Ns},
                  {"solid_fraction", r.permeability.solid_fraction},
                  {"photons", r.photons},
                  {"seed", r.seed},
                  {"mesh", r.mesh_preset},
                  {"times_s", r.times_s}}},
                {"points", pts}});
    return;
  }
  std::cout << fmt::format(
      "d = {} mm into {} mm skin over a {} s ramp, then held; water-content optics, drained Poisson's "
      "ratio {}, k0 {} mm^4/(N s), {} photons per point, seed {}, mesh '{}'\n",
      r.displacement_mm, r.thickness_mm, r.ramp_s, r.drained_poisson, r.permeability.k0_mm4_per_Ns, r.photons,
      r.seed, r.mesh_preset);
  std::cout << fmt::format("{:>9} {:>10} {:>10} {:>12} {:>15}\n", "t_hold_s", "T", "+-MC", "pin_force_N",
                           "water_out_mm3");
  for (const auto& p : points)
    std::cout << fmt::format("{:>9.2f} {:>10.6f} {:>10.6f} {:>12.6f} {:>15.6f}\n", p.time_s, p.T, p.T_stderr,
                             p.pin_force_N, p.water_outflow_mm3);
}

}  // namespace tocd::cli

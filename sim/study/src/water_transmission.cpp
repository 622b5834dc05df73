#include "water_transmission.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

#include "elapsed.hpp"
#include "tocd/sim/geometry/composite.hpp"
#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace tocd::sim::study::detail {

namespace {

geometry::SkinProfile profile_of(const poro::PoroSolver& s, double thickness) {
  geometry::SkinProfile p;
  p.thickness_mm = thickness;
  double last_r = -1;
  for (const auto& q : s.top_surface()) {
    if (q[0] <= last_r + 1e-9) continue;  // the geometry needs r strictly increasing
    p.top_surface.push_back({last_r < 0 ? 0.0 : q[0], q[1]});
    last_r = q[0];
  }
  return p;
}

}  // namespace

poro::PoroModel water_pin_model(const WaterPinGeometry& g, const material::OgdenParameters& skeleton,
                                double drained_poisson, const poro::Permeability& permeability,
                                std::function<double(double)> displacement_mm) {
  poro::PoroModel m;
  m.kinematics = poro::Kinematics::axisymmetric;
  m.mesh = {g.outer_radius_mm, g.thickness_mm, g.fe_columns, g.fe_rows, 0.4};
  m.skeleton = skeleton.mu.empty() ? published_skin_material() : skeleton;
  const double mu = m.skeleton.initial_shear_modulus(), nu = drained_poisson;
  m.skeleton.D = {3 * (1 - 2 * nu) / (mu * (1 + nu))};  // D_1 = 2 / K, K = 2 mu (1 + nu) / (3 (1 - 2 nu))
  m.permeability = permeability;
  m.left.fix_x = true;
  m.bottom.fix_x = m.bottom.fix_y = true;  // bonded to the slide, which is impermeable
  m.top.drained = m.right.drained = true;  // free surfaces drain; the pin seals its contact
  m.pin.enabled = true;
  m.pin.radius_mm = g.pin_radius_mm;
  m.pin.displacement_mm = std::move(displacement_mm);
  return m;
}

WaterTransmission water_transmission(const poro::PoroSolver& solver, const WaterPinGeometry& g,
                                     double pin_displacement_mm, const WaterMcSettings& s) {
  const auto t0 = Clock::now();
  const double phi0 = solver.model().permeability.solid_fraction;
  WaterTransmission out;
  geometry::CompositeSpec spec;
  spec.pin_radius_mm = g.pin_radius_mm;
  spec.pin_displacement_mm = pin_displacement_mm;
  spec.skin = profile_of(solver, g.thickness_mm);
  spec.size.preset = s.mesh_preset;
  geometry::CompositeMesh composite = geometry::build_composite(spec);
  out.tets_per_level = assign_water_regions(composite.mesh, s.optics, [&](double rr, double z) {
    double X = 0, Y = 0;
    if (!solver.reference_point_of(rr, z, X, Y)) return std::nan("");
    return 1 - phi0 / solver.volume_ratio_at(X, Y);
  });
  const mc::PreparedMesh prepared = mc::prepare(std::move(composite.mesh));
  out.mesh_seconds = seconds_since(t0);

  mc::Source source;
  source.kind = mc::Source::Kind::marker;
  source.marker = geometry::Marker::pin_top;
  mc::RunSettings rs;
  rs.photons = s.photons;
  rs.seed = s.seed;
  rs.threads =
      s.threads > 0 ? s.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  rs.ambient_n = 1.0;
  const mc::Result res = mc::run(prepared, water_optics(s.optics), source, rs);
  out.mc_seconds = res.seconds;
  out.T = res.transmittance.mean;
  out.T_stderr = res.transmittance.se;
  return out;
}

void record_transmission(WaterPointValues& p, const poro::PoroSolver& solver, const WaterPinGeometry& g,
                         double pin_displacement_mm, const WaterMcSettings& s) {
  p.pin_force_N = solver.state().pin_force_N;
  p.water_outflow_mm3 = solver.state().water_outflow_mm3;
  const WaterTransmission w = water_transmission(solver, g, pin_displacement_mm, s);
  p.T = w.T;
  p.T_stderr = w.T_stderr;
  p.tets_per_level = w.tets_per_level;
  p.mesh_seconds = w.mesh_seconds;
  p.mc_seconds = w.mc_seconds;
}

}  // namespace tocd::sim::study::detail

namespace tocd::sim::study {

void add_to_json(nlohmann::json& j, const WaterPointValues& v) {
  const auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  j["T"] = number(v.T);
  j["T_stderr"] = number(v.T_stderr);
  j["pin_force_N"] = number(v.pin_force_N);
  j["water_outflow_mm3"] = number(v.water_outflow_mm3);
  j["tets_per_level"] = v.tets_per_level;
  j["fe_seconds"] = v.fe_seconds;
  j["mesh_seconds"] = v.mesh_seconds;
  j["mc_seconds"] = v.mc_seconds;
}

}  // namespace tocd::sim::study

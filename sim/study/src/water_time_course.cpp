#include "tocd/sim/study/water_time_course.hpp"

#include <chrono>
#include <cmath>
#include <thread>

#include <fmt/format.h>

#include "tocd/core/error.hpp"
#include "tocd/sim/geometry/composite.hpp"
#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/poro/solver.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace tocd::sim::study {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

poro::PoroModel poro_model(const WaterTimeCourseRequest& r) {
  poro::PoroModel m;
  m.kinematics = poro::Kinematics::axisymmetric;
  m.mesh = {r.outer_radius_mm, r.thickness_mm, r.fe_columns, r.fe_rows, 0.4};
  m.skeleton = r.skeleton.mu.empty() ? published_skin_material() : r.skeleton;
  const double mu = m.skeleton.initial_shear_modulus(), nu = r.drained_poisson;
  m.skeleton.D = {3 * (1 - 2 * nu) / (mu * (1 + nu))};  // D_1 = 2 / K, K = 2 mu (1 + nu) / (3 (1 - 2 nu))
  m.permeability = r.permeability;
  m.left.fix_x = true;
  m.bottom.fix_x = m.bottom.fix_y = true;  // bonded to the slide, which is impermeable
  m.top.drained = m.right.drained = true;  // free surfaces drain; the pin seals its contact
  m.pin.enabled = true;
  m.pin.radius_mm = r.pin_radius_mm;
  const double d = r.displacement_mm, ramp = r.ramp_s;
  m.pin.displacement_mm = [d, ramp](double t) { return d * std::min(t / ramp, 1.0); };
  return m;
}

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

void validate(const WaterTimeCourseRequest& r) {
  if (!(r.thickness_mm > 0) || !(r.displacement_mm > 0) || !(r.displacement_mm < r.thickness_mm))
    throw tocd::ConfigError(
        fmt::format("water time course: displacement must lie in (0, thickness) (got {} mm of {} mm)",
                    r.displacement_mm, r.thickness_mm));
  if (!(r.ramp_s > 0))
    throw tocd::ConfigError(fmt::format("water time course: ramp_s must be > 0 (got {})", r.ramp_s));
  if (r.times_s.empty()) throw tocd::ConfigError("water time course: no time points");
  for (std::size_t i = 0; i < r.times_s.size(); ++i)
    if (!(r.times_s[i] >= 0) || (i > 0 && !(r.times_s[i] > r.times_s[i - 1])))
      throw tocd::ConfigError("water time course: time points must be >= 0 and ascending");
  if (!(r.drained_poisson > -1 && r.drained_poisson < 0.5))
    throw tocd::ConfigError(fmt::format(
        "water time course: drained Poisson's ratio must lie in (-1, 0.5) (got {})", r.drained_poisson));
  if (r.photons == 0 || r.steps_per_interval < 1)
    throw tocd::ConfigError("water time course: photons and steps_per_interval must be positive");
  native_water_fraction(r.optics);
}

std::vector<WaterTimePoint> predict_water_time_course(const WaterTimeCourseRequest& r) {
  validate(r);
  poro::PoroModel model = poro_model(r);
  const double phi0 = model.permeability.solid_fraction;
  poro::PoroSolver solver(model);
  std::vector<WaterTimePoint> out;
  // Ramp in steps_per_interval x 10 steps (large strain, contact spreading), then each
  // interval of the hold in
  // steps_per_interval steps.
  double t = 0;
  const auto advance = [&](double to, int steps) {
    const double from = t;
    for (int k = 1; k <= steps; ++k) solver.advance_to(from + (to - from) * k / steps);
    t = to;
  };
  const mc::Optics optics = water_optics(r.optics);
  for (double hold : r.times_s) {
    WaterTimePoint p;
    p.time_s = hold;
    auto t0 = Clock::now();
    if (t < r.ramp_s) advance(r.ramp_s, 10 * r.steps_per_interval);
    if (r.ramp_s + hold > t) advance(r.ramp_s + hold, r.steps_per_interval);
    p.fe_seconds = since(t0);
    p.pin_force_N = solver.state().pin_force_N;
    p.water_outflow_mm3 = solver.state().water_outflow_mm3;

    t0 = Clock::now();
    geometry::CompositeSpec spec;
    spec.pin_radius_mm = r.pin_radius_mm;
    spec.pin_displacement_mm = r.displacement_mm;
    spec.skin = profile_of(solver, r.thickness_mm);
    spec.size.preset = r.mesh_preset;
    geometry::CompositeMesh composite = geometry::build_composite(spec);
    p.tets_per_level = assign_water_regions(composite.mesh, r.optics, [&](double rr, double z) {
      double X = 0, Y = 0;
      if (!solver.reference_point_of(rr, z, X, Y)) return std::nan("");
      return 1 - phi0 / solver.volume_ratio_at(X, Y);
    });
    const mc::PreparedMesh prepared = mc::prepare(std::move(composite.mesh));
    p.mesh_seconds = since(t0);

    mc::Source source;
    source.kind = mc::Source::Kind::marker;
    source.marker = geometry::Marker::pin_top;
    mc::RunSettings s;
    s.photons = r.photons;
    s.seed = r.seed;
    s.threads =
        r.threads > 0 ? r.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    s.ambient_n = 1.0;
    const mc::Result res = mc::run(prepared, optics, source, s);
    p.mc_seconds = res.seconds;
    p.T = res.transmittance.mean;
    p.T_stderr = res.transmittance.se;
    out.push_back(p);
    if (r.progress) r.progress(out.size(), r.times_s.size());
  }
  return out;
}

nlohmann::json to_json(const WaterTimePoint& p) {
  return {{"time_s", p.time_s},
          {"T", p.T},
          {"T_stderr", p.T_stderr},
          {"pin_force_N", p.pin_force_N},
          {"water_outflow_mm3", p.water_outflow_mm3},
          {"tets_per_level", p.tets_per_level},
          {"fe_seconds", p.fe_seconds},
          {"mesh_seconds", p.mesh_seconds},
          {"mc_seconds", p.mc_seconds}};
}

}  // namespace tocd::sim::study

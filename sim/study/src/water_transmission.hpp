#pragma once

// The pieces of a water time course shared by a single ramp + hold (water_time_course.cpp)
// and a recorded displacement history (water_history.cpp): the biphasic pin model and the
// transmission of one converged FE state.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tocd/sim/material/ogden.hpp"
#include "tocd/sim/poro/model.hpp"
#include "tocd/sim/poro/solver.hpp"
#include "tocd/sim/study/water_optics.hpp"
#include "tocd/sim/study/water_point.hpp"

namespace tocd::sim::study::detail {

struct WaterPinGeometry {
  double thickness_mm = 2.5, outer_radius_mm = 6.25, pin_radius_mm = 1.5;
  int fe_columns = 24, fe_rows = 8;
};

/// The axisymmetric biphasic pin problem: skin bonded to the impermeable slide, free surfaces
/// drained, the published Ogden skeleton (unless `skeleton` is given) with D_1 from the drained
/// Poisson's ratio, the pin following `displacement_mm(t)`.
poro::PoroModel water_pin_model(const WaterPinGeometry& g, const material::OgdenParameters& skeleton,
                                double drained_poisson, const poro::Permeability& permeability,
                                std::function<double(double)> displacement_mm);

struct WaterTransmission {
  double T = 0, T_stderr = 0;
  std::vector<std::size_t> tets_per_level;
  double mesh_seconds = 0, mc_seconds = 0;
};

/// The solver's current state as the skin of the composite mesh (pin at `pin_displacement_mm`),
/// water levels from the FE field at each skin tet's centroid, photon Monte Carlo.
WaterTransmission water_transmission(const poro::PoroSolver& solver, const WaterPinGeometry& g,
                                     double pin_displacement_mm, const WaterMcSettings& s);

/// `p`'s pin force and outflow from the solver's current state, and T, its mesh's levels and
/// their times from the transmission of that state (water_transmission above).
void record_transmission(WaterPointValues& p, const poro::PoroSolver& solver, const WaterPinGeometry& g,
                         double pin_displacement_mm, const WaterMcSettings& s);

}  // namespace tocd::sim::study::detail

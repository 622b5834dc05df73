#pragma once

#include "tocd/sim/material/ogden.hpp"

namespace tocd::sim::material {

/// The law `law` made `s` times stiffer with the same shape and Poisson's ratio: every shear
/// modulus mu_i times s, every D_i divided by s (the bulk modulus scales with mu). A
/// displacement-driven solve then gives the same deformation and s times the loads.
OgdenParameters scale_stiffness(const OgdenParameters& law, double s);

}  // namespace tocd::sim::material

#pragma once

#include <nlohmann/json.hpp>

#include "tocd/sim/fe/result.hpp"
#include "tocd/sim/geometry/composite.hpp"

namespace tocd::sim::study {

/// The deformed skin of one FE step as the geometry module's profile (same r-z frame).
/// Tidies what TetGen would reject: points of the top surface that do not advance in r
/// (within 1e-9 mm) are dropped and the surface starts at r = 0; compressed outlines lose
/// repeated points, are turned counter-clockwise, and outlines with fewer than 3 points or
/// no area are dropped. Outlines are otherwise passed on as the FE gives them: where they run
/// along the top surface under the pin, the geometry takes the skin top (and the pin/skin
/// contact surface) as their boundary. Throws tocd::Error when the top surface has fewer
/// than 2 points.
geometry::SkinProfile to_skin_profile(const fe::FeStepResult& step, double thickness_mm);

/// The flat, undeformed skin (no FE needed at zero displacement).
geometry::SkinProfile flat_skin_profile(double thickness_mm);

/// A short description of an FE step for logs and the prediction's artefacts: displacement,
/// force, Newton iterations, compressed area and volume, outline count, the lowest point of
/// the top surface and the log strain just under the pin tip.
nlohmann::json summarise(const fe::FeStepResult& step);

}  // namespace tocd::sim::study

#include "tocd/sim/study/profile_adapter.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "tocd/core/error.hpp"

namespace tocd::sim::study {
namespace {

constexpr double kTol = 1e-9;

double signed_area(const std::vector<geometry::ProfilePoint>& poly) {
  double a = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& p = poly[i];
    const auto& q = poly[(i + 1) % poly.size()];
    a += p.r_mm * q.z_mm - q.r_mm * p.z_mm;
  }
  return 0.5 * a;
}

}  // namespace

geometry::SkinProfile to_skin_profile(const fe::FeStepResult& step, double thickness_mm) {
  geometry::SkinProfile profile;
  profile.thickness_mm = thickness_mm;
  for (const auto& p : step.top_surface) {
    const geometry::ProfilePoint q{std::max(p.r_mm, 0.0), p.z_mm};
    if (!profile.top_surface.empty() && q.r_mm <= profile.top_surface.back().r_mm + kTol) continue;
    if (profile.top_surface.empty() && q.r_mm > kTol) profile.top_surface.push_back({0.0, q.z_mm});
    profile.top_surface.push_back(q);
  }
  if (profile.top_surface.size() < 2)
    throw tocd::Error(fmt::format("FE step at {} mm: the deformed top surface has {} usable points (need 2)",
                                  step.displacement_mm, profile.top_surface.size()));
  profile.top_surface.front().r_mm = 0.0;
  for (const auto& outline : step.compressed_outlines) {
    std::vector<geometry::ProfilePoint> poly;
    for (const auto& p : outline) {
      const geometry::ProfilePoint q{std::max(p.r_mm, 0.0), p.z_mm};
      if (!poly.empty() && std::abs(q.r_mm - poly.back().r_mm) < kTol &&
          std::abs(q.z_mm - poly.back().z_mm) < kTol)
        continue;
      poly.push_back(q);
    }
    while (poly.size() > 1 && std::abs(poly.front().r_mm - poly.back().r_mm) < kTol &&
           std::abs(poly.front().z_mm - poly.back().z_mm) < kTol)
      poly.pop_back();
    if (poly.size() < 3) continue;
    const double area = signed_area(poly);
    if (std::abs(area) < 1e-8) continue;
    if (area < 0) std::reverse(poly.begin(), poly.end());
    profile.compressed_outlines.push_back(std::move(poly));
  }
  return profile;
}

geometry::SkinProfile flat_skin_profile(double thickness_mm) {
  geometry::SkinProfile profile;  // an empty top surface is the flat skin
  profile.thickness_mm = thickness_mm;
  return profile;
}

nlohmann::json summarise(const fe::FeStepResult& step) {
  double z_min = std::numeric_limits<double>::infinity();
  for (const auto& p : step.top_surface) z_min = std::min(z_min, p.z_mm);
  nlohmann::json j;
  j["displacement_mm"] = step.displacement_mm;
  j["force_N"] = step.force_N;
  j["newton_iterations"] = step.newton_iterations;
  j["compressed_area_mm2"] = step.compressed_area_mm2;
  j["compressed_volume_mm3"] = step.compressed_volume_mm3;
  j["compressed_outlines"] = step.compressed_outlines.size();
  j["top_surface_points"] = step.top_surface.size();
  if (std::isfinite(z_min)) {
    j["top_surface_min_z_mm"] = z_min;
    // Just below the deformed surface on the axis: where the strain is largest.
    const double e = step.min_log_strain_at(0.0, z_min - 1e-3);
    if (std::isfinite(e)) j["min_log_strain_under_tip"] = e;
  }
  return j;
}

}  // namespace tocd::sim::study

#include "step_output.hpp"

#include <cmath>
#include <numbers>

#include "tocd/sim/fe/locator.hpp"

namespace tocd::sim::fe {

namespace {
// Area and first moment int r dA of a closed polygon (positive when counter-clockwise).
void polygon_moments(const std::vector<Point2>& p, double& area, double& r_moment) {
  area = r_moment = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const Point2& a = p[k];
    const Point2& b = p[(k + 1) % p.size()];
    area += 0.5 * (a.r_mm * b.z_mm - b.r_mm * a.z_mm);
    // Green's theorem: int r dA = closed int r^2/2 dz, exact for straight edges.
    r_moment += (b.z_mm - a.z_mm) * (a.r_mm * a.r_mm + a.r_mm * b.r_mm + b.r_mm * b.r_mm) / 6.0;
  }
}
}  // namespace

FeStepResult make_step_result(const FeModel& model, const tocd::sim::material::HyperelasticLaw& law,
                              const Assembly& assembly, const Eigen::VectorXd& u, const Evaluation& ev,
                              double displacement_mm) {
  FeStepResult s;
  s.displacement_mm = displacement_mm;
  s.compressed_log_strain = model.compressed_log_strain;
  const bool axi = model.kinematics == Kinematics::axisymmetric;
  const double out_of_plane = axi ? 2 * std::numbers::pi : 2 * model.depth_mm;
  s.force_N = ev.pin_force * out_of_plane;
  s.max_penetration_mm = std::max(0.0, ev.max_penetration);
  s.contact_radius_mm = ev.contact_radius;
  const FeMesh& ref = assembly.mesh();
  s.mesh = ref;
  for (std::size_t n = 0; n < ref.nodes.size(); ++n) {
    s.displacement.push_back({u[2 * n], u[2 * n + 1]});
    s.mesh.nodes[n].r_mm += u[2 * n];
    s.mesh.nodes[n].z_mm += u[2 * n + 1];
  }
  for (int n : assembly.top_nodes()) s.top_surface.push_back(s.mesh.nodes[n]);
  std::vector<char> flagged(ref.quads.size(), 0);
  for (std::size_t e = 0; e < ref.quads.size(); ++e) {
    std::array<std::array<double, 2>, 4> x;
    for (int a = 0; a < 4; ++a)
      x[a] = {s.mesh.nodes[ref.quads[e][a]].r_mm, s.mesh.nodes[ref.quads[e][a]].z_mm};
    ElementStrain es;
    element_strain(assembly.references()[e], x, model.kinematics, law, es);
    s.element_min_log_strain.push_back(es.min_log_strain);
    s.element_J.push_back(es.J);
    flagged[e] = es.min_log_strain <= model.compressed_log_strain;
  }
  for (const auto& loop : region_loops(ref, flagged)) {
    std::vector<Point2> poly;
    for (int n : loop) poly.push_back(s.mesh.nodes[n]);
    double area, rm;
    polygon_moments(poly, area, rm);
    s.compressed_area_mm2 += area;
    s.compressed_volume_mm3 += axi ? 2 * std::numbers::pi * rm : 2 * model.depth_mm * area;
    s.compressed_outlines.push_back(std::move(poly));
  }
  s.locator = std::make_shared<const PointLocator>(s.mesh);
  return s;
}

}  // namespace tocd::sim::fe

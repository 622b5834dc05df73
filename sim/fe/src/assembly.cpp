#include "assembly.hpp"

#include <algorithm>
#include <cmath>

namespace tocd::sim::fe {

void PinGeometry::query(double r, double z, double& gap, Eigen::Vector2d& n,
                        double& curvature_distance) const {
  const double zc = tip_z + radius;
  if (z < zc) {
    const Eigen::Vector2d v(r, z - zc);
    const double dist = v.norm();
    if (dist < 1e-12 * radius) {  // at the centre: any direction; pick straight down
      n = Eigen::Vector2d(0, -1);
      gap = -radius;
      curvature_distance = radius;
      return;
    }
    n = v / dist;
    gap = dist - radius;
    curvature_distance = dist;
  } else {
    n = Eigen::Vector2d(1, 0);
    gap = r - radius;
    curvature_distance = 0;
  }
}

Assembly::Assembly(const FeModel& model, FeMesh mesh, const tocd::sim::material::HyperelasticLaw& law)
    : model_(model), mesh_(std::move(mesh)), law_(law) {
  const int nn = static_cast<int>(mesh_.nodes.size());
  eq_.assign(2 * nn, 0);
  for (int j = 0; j < mesh_.nodes_z; ++j)
    for (int i = 0; i < mesh_.nodes_r; ++i) {
      const int n = j * mesh_.nodes_r + i;
      if (i == 0) eq_[2 * n] = -1;  // axis / symmetry plane
      if (j == 0) {
        eq_[2 * n + 1] = -1;  // resting on the slide
        if (model_.bottom == Bottom::bonded) eq_[2 * n] = -1;
      }
    }
  for (int& e : eq_)
    if (e == 0) e = free_++;
  for (int i = 0; i < mesh_.nodes_r; ++i) top_.push_back((mesh_.nodes_z - 1) * mesh_.nodes_r + i);
  penalty.assign(top_.size(), 0.0);
  multiplier.assign(top_.size(), 0.0);

  refs_.reserve(mesh_.quads.size());
  std::vector<Eigen::Triplet<double>> trip;
  for (const auto& q : mesh_.quads) {
    std::array<std::array<double, 2>, 4> X;
    for (int a = 0; a < 4; ++a) X[a] = {mesh_.nodes[q[a]].r_mm, mesh_.nodes[q[a]].z_mm};
    refs_.push_back(make_element_reference(X, model_.kinematics));
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        const int ea = eq_[2 * q[a / 2] + a % 2], eb = eq_[2 * q[b / 2] + b % 2];
        if (ea >= 0 && eb >= 0) trip.emplace_back(ea, eb, 0.0);
      }
  }
  K_.resize(free_, free_);
  K_.setFromTriplets(trip.begin(), trip.end());
  K_.makeCompressed();
  auto slot = [&](int row, int col) -> int {
    if (row < 0 || col < 0) return -1;
    const int* begin = K_.innerIndexPtr() + K_.outerIndexPtr()[col];
    const int* end = K_.innerIndexPtr() + K_.outerIndexPtr()[col + 1];
    const int* it = std::lower_bound(begin, end, row);
    return static_cast<int>(it - K_.innerIndexPtr());
  };
  for (const auto& q : mesh_.quads) {
    std::array<int, 64> s;
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) s[8 * a + b] = slot(eq_[2 * q[a / 2] + a % 2], eq_[2 * q[b / 2] + b % 2]);
    slots_.push_back(s);
  }
  for (int n : top_)
    top_slots_.push_back({slot(eq_[2 * n], eq_[2 * n]), slot(eq_[2 * n], eq_[2 * n + 1]),
                          slot(eq_[2 * n + 1], eq_[2 * n]), slot(eq_[2 * n + 1], eq_[2 * n + 1])});
}

void Assembly::evaluate(const Eigen::VectorXd& u, double tip_z, bool want_stiffness, Evaluation& ev) {
  ev.valid = false;
  ev.energy = 0;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(dofs());
  double* Kv = K_.valuePtr();
  if (want_stiffness) std::fill(Kv, Kv + K_.nonZeros(), 0.0);
  ElementResponse er;
  for (std::size_t e = 0; e < mesh_.quads.size(); ++e) {
    const auto& q = mesh_.quads[e];
    std::array<std::array<double, 2>, 4> x;
    for (int a = 0; a < 4; ++a)
      x[a] = {mesh_.nodes[q[a]].r_mm + u[2 * q[a]], mesh_.nodes[q[a]].z_mm + u[2 * q[a] + 1]};
    if (!element_response(refs_[e], x, model_.kinematics, law_, want_stiffness, er)) return;  // inverted
    ev.energy += er.energy;
    for (int a = 0; a < 8; ++a) f[2 * q[a / 2] + a % 2] += er.force[a];
    if (want_stiffness) {
      const auto& s = slots_[e];
      for (int k = 0; k < 64; ++k)
        if (s[k] >= 0) Kv[s[k]] += er.stiffness(k / 8, k % 8);
    }
  }
  ev.internal_force_norm = f.norm();
  ev.contact_force.assign(top_.size(), 0.0);
  if (want_stiffness) {
    ev.top_stiffness.assign(top_.size(), 0.0);
    for (std::size_t t = 0; t < top_.size(); ++t)
      for (int k : {0, 3})
        if (top_slots_[t][k] >= 0) ev.top_stiffness[t] = std::max(ev.top_stiffness[t], Kv[top_slots_[t][k]]);
  }
  ev.pin_force = ev.max_penetration = ev.contact_radius = 0;
  for (std::size_t t = 0; t < top_.size(); ++t) {
    const int n = top_[t];
    const PinContact c = pin_contact(t, u, tip_z);
    const double g = c.gap, dist = c.curvature_distance, r = mesh_.nodes[n].r_mm + u[2 * n];
    const Eigen::Vector2d& nv = c.normal;
    ev.max_penetration = std::max(ev.max_penetration, -g);
    const double k = penalty[t];
    const double p = std::max(0.0, multiplier[t] - k * g);
    if (p <= 0) continue;
    ev.energy += p * p / (2 * k);
    ev.contact_force[t] = p;
    ev.contact_radius = std::max(ev.contact_radius, r);
    ev.pin_force += -p * nv[1];
    f[2 * n] -= p * nv[0];
    f[2 * n + 1] -= p * nv[1];
    if (!want_stiffness) continue;
    Eigen::Matrix2d kc = k * nv * nv.transpose();
    if (dist > 0) kc -= p / dist * (Eigen::Matrix2d::Identity() - nv * nv.transpose());
    for (int k4 = 0; k4 < 4; ++k4)
      if (top_slots_[t][k4] >= 0) Kv[top_slots_[t][k4]] += kc(k4 / 2, k4 % 2);
  }
  ev.residual.resize(free_);
  for (int d = 0; d < dofs(); ++d)
    if (eq_[d] >= 0) ev.residual[eq_[d]] = f[d];
  ev.residual_norm = ev.residual.norm();
  ev.valid = std::isfinite(ev.energy) && std::isfinite(ev.residual_norm);
}

PinContact Assembly::pin_contact(std::size_t t, const Eigen::VectorXd& u, double tip_z) const {
  const int n = top_[t];
  PinContact c;
  PinGeometry{model_.pin_radius_mm, tip_z}.query(mesh_.nodes[n].r_mm + u[2 * n],
                                                 mesh_.nodes[n].z_mm + u[2 * n + 1], c.gap, c.normal,
                                                 c.curvature_distance);
  return c;
}

}  // namespace tocd::sim::fe

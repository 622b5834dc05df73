#include "tocd/sim/poro/solver.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <fmt/format.h>

#include "dof_map.hpp"
#include "element.hpp"
#include "grid.hpp"
#include "pin_contact.hpp"
#include "pore_closure.hpp"
#include "tocd/sim/material/hyperelastic.hpp"

namespace tocd::sim::poro {

namespace mat = tocd::sim::material;

struct PoroSolver::Impl {
  PoroModel model;
  Grid grid;
  DofMap dofs;
  std::unique_ptr<mat::HyperelasticLaw> skeleton;
  std::vector<ElementGauss> gauss;
  Eigen::VectorXd values;  // every dof, converged at state.time_s
  PoroState state;
  // Pin contact: multipliers (normal force per top node), penalties, and which top pressure
  // nodes the glass seals (from the last converged contact).
  std::vector<double> multipliers, penalties, contact_forces;
  std::vector<bool> sealed_top;
  // Top nodes whose contact force enters the equations; fixed during one Newton solve (see
  // step_to).
  std::vector<char> active;
  static constexpr int kMaxActiveSetPasses = 20;
  mutable double energy_scale = 0;  // largest first-iteration Newton energy seen

  explicit Impl(PoroModel m) : model(std::move(m)) {
    model.validate();
    grid = make_grid(model.mesh);
    dofs = make_dof_map(grid, model);
    skeleton = make_skeleton_law(model);
    for (int e = 0; e < grid.element_count(); ++e)
      gauss.push_back(make_element_gauss(grid.element_box(e), model.kinematics));
    values = Eigen::VectorXd::Zero(dofs.pressure_offset + grid.pressure_count());
    if (model.pin.enabled) {
      const double mu0 = model.skeleton.initial_shear_modulus();
      const double quarter = 0.25 * model.mesh.width_mm / model.mesh.nx;
      for (int i = 0; i <= 2 * grid.nx; ++i) {
        const double ring = model.kinematics == Kinematics::axisymmetric
                                ? 2 * std::numbers::pi * std::max(grid.xs[i], quarter)
                                : 1.0;
        penalties.push_back(model.pin.penalty_factor * mu0 * ring);
      }
      multipliers.assign(penalties.size(), 0.0);
      contact_forces.assign(penalties.size(), 0.0);
      active.assign(penalties.size(), 0);
      sealed_top.assign(grid.nx + 1, false);
    }
  }

  double pin_centre(double t) const {
    return model.mesh.height_mm - model.pin.displacement_mm(t) + model.pin.radius_mm;
  }

  // The top node on the axis of an axisymmetric model stays in contact while its neighbour
  // is: its consistent nodal force vanishes (ring weight 2 pi r = 0), so its contact status
  // is undecided by force. Held, it pulls on the pin by a few um of penalty; free, it
  // penetrates, and once the active-set rule had released it for good (released twice) its
  // vertical motion was held by nothing but the axis element: under a 1.5 mm pin, with that
  // element compacted toward its solid volume, Newton steps moved it by up to 3 mm and the
  // iteration did not converge (docs/water.md, "State").
  bool axis_node_held() const {
    return model.kinematics == Kinematics::axisymmetric && active.size() > 1 && active[1];
  }

  // Contact force of top node i at state x: N = lambda - eps g along the pin normal (the
  // active set decides where it acts; the converged contact has N >= 0 there).
  struct NodeContact {
    PinGap gap;
    double force = 0;
  };
  NodeContact node_contact(const Eigen::VectorXd& x, int i, double centre) const {
    const int n = grid.node(i, 2 * grid.ny);
    NodeContact c;
    c.gap = pin_gap(grid.xs[i] + x[2 * n], grid.ys.back() + x[2 * n + 1], model.pin.radius_mm, centre);
    c.force = multipliers[i] - penalties[i] * c.gap.gap;
    return c;
  }

  void add_contact(const Eigen::VectorXd& x, double t, Eigen::VectorXd& internal,
                   std::vector<Eigen::Triplet<double>>* triplets) const {
    const double centre = pin_centre(t);
    for (int i = 0; i <= 2 * grid.nx; ++i) {
      if (!active[i]) continue;
      const NodeContact c = node_contact(x, i, centre);
      const int n = grid.node(i, 2 * grid.ny);
      const Eigen::Vector2d& nv = c.gap.normal;
      for (int a = 0; a < 2; ++a) internal[2 * n + a] -= c.force * nv[a];
      if (!triplets) continue;
      // d(-N n)/dx = eps n n^T - N kappa (I - n n^T)
      const Eigen::Matrix2d nn = nv * nv.transpose();
      const Eigen::Matrix2d k =
          penalties[i] * nn - c.force * c.gap.curvature * (Eigen::Matrix2d::Identity() - nn);
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          const int ea = dofs.equation[2 * n + a], eb = dofs.equation[2 * n + b];
          if (ea >= 0 && eb >= 0) triplets->emplace_back(ea, eb, k(a, b));
        }
    }
  }

  std::array<int, kElementDofs> element_dofs(int e) const {
    std::array<int, kElementDofs> d{};
    const auto n = grid.element_nodes(e);
    const auto pn = grid.element_pressure_nodes(e);
    for (int a = 0; a < 9; ++a) {
      d[2 * a] = 2 * n[a];
      d[2 * a + 1] = 2 * n[a] + 1;
    }
    for (int c = 0; c < 4; ++c) d[18 + c] = dofs.pressure_offset + pn[c];
    return d;
  }

  ElementVector gather(const Eigen::VectorXd& v, const std::array<int, kElementDofs>& d) const {
    ElementVector out;
    for (int i = 0; i < kElementDofs; ++i) out[i] = v[d[i]];
    return out;
  }

  // Dead-load tractions of the side pressures and the plate force at time t (per dof).
  Eigen::VectorXd external_forces(double t) const {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(values.size());
    const double g = std::sqrt(0.6), pts[3] = {-g, 0, g}, wts[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    const bool axi = model.kinematics == Kinematics::axisymmetric;
    auto load_line = [&](const std::vector<double>& lines, bool along_x, double fixed_coord, int fixed_index,
                         double normal_sign, double q) {
      const int n = static_cast<int>(lines.size() - 1) / 2;
      for (int e = 0; e < n; ++e) {
        const double a = lines[2 * e], b = lines[2 * e + 2];
        for (int k = 0; k < 3; ++k) {
          const double s = pts[k], pos = 0.5 * (a + b) + 0.5 * (b - a) * s;
          const double R = along_x ? pos : fixed_coord;
          double w = wts[k] * 0.5 * (b - a) * (axi ? 2 * std::numbers::pi * R : 1.0);
          const double N[3] = {0.5 * s * (s - 1), 1 - s * s, 0.5 * s * (s + 1)};
          for (int l = 0; l < 3; ++l) {
            const int node = along_x ? grid.node(2 * e + l, fixed_index) : grid.node(fixed_index, 2 * e + l);
            // traction -q n: the normal is along y for horizontal sides, along x for vertical ones
            f[2 * node + (along_x ? 1 : 0)] += -q * normal_sign * N[l] * w;
          }
        }
      }
    };
    const double W = model.mesh.width_mm;
    if (model.left.normal_pressure) load_line(grid.ys, false, 0.0, 0, -1, model.left.normal_pressure(t));
    if (model.right.normal_pressure)
      load_line(grid.ys, false, W, 2 * grid.nx, +1, model.right.normal_pressure(t));
    if (model.bottom.normal_pressure) load_line(grid.xs, true, 0.0, 0, -1, model.bottom.normal_pressure(t));
    if (model.top.normal_pressure)
      load_line(grid.xs, true, 0.0, 2 * grid.ny, +1, model.top.normal_pressure(t));
    if (dofs.plate_equation >= 0) f[dofs.plate_dofs.front()] -= model.plate.force_N(t);
    return f;
  }

  // Internal force per dof and (optionally) the tangent in equation numbering.
  bool assemble(const Eigen::VectorXd& x, double t, double dt, Eigen::VectorXd& internal,
                std::vector<Eigen::Triplet<double>>* triplets) const {
    internal = Eigen::VectorXd::Zero(x.size());
    const ElementPhysics physics{model.kinematics, skeleton.get(), &model.permeability, dt};
    ElementVector r;
    ElementMatrix K;
    for (int e = 0; e < grid.element_count(); ++e) {
      const auto d = element_dofs(e);
      if (!element_residual(gauss[e], physics, gather(x, d), gather(values, d), r, triplets ? &K : nullptr))
        return false;
      for (int i = 0; i < kElementDofs; ++i) {
        internal[d[i]] += r[i];
        if (!triplets) continue;
        const int ei = dofs.equation[d[i]];
        if (ei < 0) continue;
        for (int j = 0; j < kElementDofs; ++j) {
          const int ej = dofs.equation[d[j]];
          if (ej >= 0) triplets->emplace_back(ei, ej, K(i, j));
        }
      }
    }
    if (model.pin.enabled) add_contact(x, t, internal, triplets);
    return true;
  }

  Eigen::VectorXd reduce(const Eigen::VectorXd& per_dof) const {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(dofs.equation_count);
    for (int d = 0; d < per_dof.size(); ++d)
      if (dofs.equation[d] >= 0) r[dofs.equation[d]] += per_dof[d];
    return r;
  }

  double water_content_change(const Eigen::VectorXd& x) const {
    double change = 0;
    for (int e = 0; e < grid.element_count(); ++e) {
      const ElementVector u = gather(x, element_dofs(e));
      const auto box = grid.element_box(e);
      const double g = std::sqrt(0.6), pts[3] = {-g, 0, g};
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
          change += (element_volume_ratio(box, model.kinematics, u, pts[i], pts[j]) - 1) *
                    gauss[e][3 * j + i].weight;
    }
    return change;
  }

  // Newton iterations of one backward-Euler step from x; `internal` ends at the converged x.
  int newton(Eigen::VectorXd& x, double t, double dt, const Eigen::VectorXd& f_ext,
             Eigen::VectorXd& internal) const {
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::SparseMatrix<double> K(dofs.equation_count, dofs.equation_count);
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    double first_energy = -1, previous_energy = 0;
    for (int it = 0;; ++it) {
      if (it >= model.solver.max_newton_iterations)
        throw PoroError(
            fmt::format("Newton did not converge in {} iterations at t = {} s (dt = {} s)", it, t, dt));
      triplets.clear();
      if (!assemble(x, t, dt, internal, &triplets))
        throw PoroError(fmt::format("inadmissible state (J <= phi0 or inverted element) at t = {} s", t));
      const Eigen::VectorXd r = reduce(internal - f_ext);
      K.setFromTriplets(triplets.begin(), triplets.end());
      lu.compute(K);
      if (lu.info() != Eigen::Success) throw PoroError(fmt::format("singular tangent at t = {} s", t));
      const Eigen::VectorXd du = lu.solve(-r);
      const double energy = std::abs(r.dot(du));
      if (first_energy < 0) first_energy = energy;
      // Round-off floor, measured against the largest first-iteration energy of any step so
      // far (late in a hold a step changes little, so its own first energy is no scale):
      // converged below 1e-24 of it, or once below 1e-14 of it and no longer falling.
      energy_scale = std::max(energy_scale, first_energy);
      const bool stagnant = it >= 2 && energy >= 0.1 * previous_energy && energy <= 1e-14 * energy_scale;
      if (energy <= model.solver.energy_tolerance * first_energy || energy <= 1e-24 * energy_scale ||
          stagnant || energy == 0)
        return it;
      previous_energy = energy;
      // Halve the step until the state is admissible.
      double scale = 1;
      for (int cut = 0;; ++cut) {
        Eigen::VectorXd trial = x;
        for (int d = 0; d < x.size(); ++d)
          if (dofs.equation[d] >= 0) trial[d] += scale * du[dofs.equation[d]];
        Eigen::VectorXd probe;
        if (assemble(trial, t, dt, probe, nullptr)) {
          x = trial;
          break;
        }
        if (cut == 20) throw PoroError(fmt::format("no admissible Newton step at t = {} s", t));
        scale *= 0.5;
      }
    }
  }

  const PoroState& advance_to(double t) {
    if (!(t > state.time_s) || !std::isfinite(t))
      throw PoroError(fmt::format("time {} s does not advance the state at {} s", t, state.time_s));
    // Adaptive backward Euler: a step whose Newton iteration fails (contact set not settling,
    // no admissible iterate, no convergence) is retried as two half steps, down to 1/1024 of
    // the requested step. Each sub-step is a converged backward-Euler state, so the water
    // balance and the sealing (which follows the previous sub-step's contact) stay consistent.
    constexpr int kMaxHalvings = 10;
    std::vector<double> targets{t};
    int iterations = 0, halvings = 0;
    while (!targets.empty()) {
      const double next = targets.back();
      try {
        step_to(next);
        iterations += state.newton_iterations;
        targets.pop_back();
      } catch (const PoroError& e) {
        const double half = 0.5 * (state.time_s + next);
        if (static_cast<int>(targets.size()) > kMaxHalvings || !(half > state.time_s && half < next))
          throw PoroError(fmt::format("{} (after halving the step {} times)", e.what(), targets.size() - 1));
        targets.push_back(half);
        ++halvings;
      }
    }
    state.newton_iterations = iterations;
    state.step_halvings = halvings;
    return state;
  }

  // One backward-Euler step to t; throws PoroError with the state and the contact unchanged.
  void step_to(double t) {
    const double dt = t - state.time_s;
    const auto saved_multipliers = multipliers, saved_forces = contact_forces;
    const auto saved_active = active;
    const double saved_energy_scale = energy_scale;
    const DofMap saved_dofs = dofs;
    try {
      if (model.pin.enabled) dofs = make_dof_map(grid, model, sealed_top);
      Eigen::VectorXd x = values;
      for (int d : dofs.drained_pressures) x[d] = 0;
      if (model.plate.enabled && model.plate.displacement_mm)
        for (int d : dofs.plate_dofs) x[d] = -model.plate.displacement_mm(t);
      const Eigen::VectorXd f_ext = external_forces(t);
      Eigen::VectorXd internal;
      int iterations = 0;
      double penetration = 0;
      const double centre = model.pin.enabled ? pin_centre(t) : 0;
      const double depth = model.pin.enabled
                               ? std::max(std::abs(model.pin.displacement_mm(t)), 1e-6 * model.mesh.height_mm)
                               : 0;
      const double gap_tolerance = model.pin.penetration_tolerance * depth;
      // Active set of the first iteration: the nodes the pin reaches at the start of the step.
      if (model.pin.enabled)
        for (std::size_t i = 0; i < active.size(); ++i) {
          active[i] = node_contact(x, int(i), centre).force > 0 || (i == 0 && axis_node_held());
          if (!active[i]) multipliers[i] = 0;
        }
      for (int aug = 0;; ++aug) {
        // Contact as an active-set strategy: Newton runs with the set fixed (a smooth problem,
        // contact forces of the set may turn tensile meanwhile), then the set is corrected and
        // Newton rerun until no node is on the wrong side. Deciding the set inside Newton from
        // each iterate instead (semi-smooth Newton, as before) makes nodes near zero force
        // chatter: the axis node of the Q9 top carries no consistent force under a smooth
        // pressure, its status flipped every iteration, the iterates diverged, and step
        // halving ran out of admissible states. The band is the penetration tolerance: a node
        // joins once it penetrates beyond it, leaves once its tension exceeds the penalty times
        // it (the same accuracy the augmentation accepts). A node released twice in a step is
        // not taken back: the axis node otherwise alternated for ever between penetrating
        // (free) and pulling the pin (held), 16 um and 4 um beyond the 1.25 um band (1.25 mm,
        // nu = 0.3, ramp 1 s); its penetration is then reported in max_penetration_mm.
        std::vector<int> releases(active.size(), 0);
        for (int pass = 0;; ++pass) {
          iterations += newton(x, t, dt, f_ext, internal);
          if (!model.pin.enabled) break;
          bool changed = false;
          for (std::size_t i = 0; i < active.size(); ++i) {
            const double band = penalties[i] * gap_tolerance, f = node_contact(x, int(i), centre).force;
            if (active[i] && f < -band && !(i == 0 && axis_node_held())) {
              active[i] = 0;  // released: it carries nothing, its multiplier with it
              multipliers[i] = 0;
              ++releases[i];
              changed = true;
            } else if (!active[i] && f > band && releases[i] < 2) {
              active[i] = 1;
              changed = true;
            }
          }
          if (!changed) break;
          if (pass >= kMaxActiveSetPasses)
            throw PoroError(fmt::format("contact active set did not settle at t = {} s", t));
        }
        if (!model.pin.enabled) break;
        // Augmented Lagrangian: multipliers take the converged contact forces.
        penetration = 0;
        for (std::size_t i = 0; i < multipliers.size(); ++i) {
          const NodeContact c = node_contact(x, static_cast<int>(i), centre);
          if (active[i]) penetration = std::max(penetration, -c.gap.gap);
          contact_forces[i] = active[i] ? c.force : 0.0;
          multipliers[i] = std::max(0.0, contact_forces[i]);
        }
        if (penetration <= gap_tolerance || aug >= model.pin.max_augmentations) break;
      }
      commit(x, internal, t, iterations, penetration);
    } catch (const PoroError&) {
      multipliers = saved_multipliers;
      contact_forces = saved_forces;
      active = saved_active;
      energy_scale = saved_energy_scale;
      dofs = saved_dofs;
      throw;
    }
  }

  void commit(const Eigen::VectorXd& x, const Eigen::VectorXd& internal, double t, int iterations,
              double penetration) {
    // Water through drained sides: minus the Darcy residual there (its sum over all nodes is
    // int (J - J_n) dV, the water taken up).
    double outflow = 0;
    for (int d : dofs.drained_pressures) outflow -= internal[d];
    values = x;
    state.time_s = t;
    state.newton_iterations = iterations;
    state.water_outflow_mm3 += outflow;
    state.water_content_change_mm3 = water_content_change(values);
    if (model.plate.enabled) {
      state.plate_displacement_mm = -values[dofs.plate_dofs.front()];
      double force = 0;
      for (int d : dofs.plate_dofs) force -= internal[d];
      state.plate_force_N = force;
    }
    if (model.pin.enabled) {
      const double centre = pin_centre(t);
      state.pin_force_N = 0;
      state.pin_contact_radius_mm = 0;
      // Largest penetration of any top node (a node kept out of the set may penetrate).
      state.max_penetration_mm = penetration;
      for (int i = 0; i <= 2 * grid.nx; ++i)
        state.max_penetration_mm =
            std::max(state.max_penetration_mm, -node_contact(values, i, centre).gap.gap);
      for (int i = 0; i <= 2 * grid.nx; ++i) {
        const NodeContact c = node_contact(values, i, centre);
        if (!active[i]) continue;
        state.pin_force_N += -contact_forces[i] * c.gap.normal[1];
        const int n = grid.node(i, 2 * grid.ny);
        state.pin_contact_radius_mm = std::max(state.pin_contact_radius_mm, grid.xs[i] + values[2 * n]);
      }
      // The glass seals the top for the next step from the axis to the contact edge: every
      // pressure node whose current radius lies within the contact radius. Not node by node
      // from the nodal forces: under a smooth contact pressure a corner node of the Q9 top
      // carries little or no consistent force (none on the axis), which left the axis node
      // drained under the middle of the pin and the sealed set full of holes.
      bool any = false;
      for (int i = 0; i <= 2 * grid.nx; ++i) any = any || active[i];
      for (int i = 0; i <= grid.nx; ++i) {
        const int n = grid.node(2 * i, 2 * grid.ny);
        sealed_top[i] = any && grid.xs[2 * i] + values[2 * n] <= state.pin_contact_radius_mm;
      }
    }
  }
};

std::vector<Eigen::Vector2d> PoroSolver::top_surface() const {
  const Grid& g = impl_->grid;
  std::vector<Eigen::Vector2d> out;
  for (int i = 0; i <= 2 * g.nx; ++i) {
    const int n = g.node(i, 2 * g.ny);
    out.emplace_back(g.xs[i] + impl_->values[2 * n], g.ys.back() + impl_->values[2 * n + 1]);
  }
  return out;
}

bool PoroSolver::reference_point_of(double x_mm, double y_mm, double& X_mm, double& Y_mm) const {
  const Grid& g = impl_->grid;
  const Eigen::Vector2d target(x_mm, y_mm);
  for (int e = 0; e < g.element_count(); ++e) {
    const auto nodes = g.element_nodes(e);
    const auto box = g.element_box(e);
    Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300), xa[9];
    for (int a = 0; a < 9; ++a) {
      const int n = nodes[a], i = n % (2 * g.nx + 1), j = n / (2 * g.nx + 1);
      xa[a] = Eigen::Vector2d(g.xs[i] + impl_->values[2 * n], g.ys[j] + impl_->values[2 * n + 1]);
      lo = lo.cwiseMin(xa[a]);
      hi = hi.cwiseMax(xa[a]);
    }
    const Eigen::Vector2d pad = 0.05 * (hi - lo);
    if ((target.array() < (lo - pad).array()).any() || (target.array() > (hi + pad).array()).any()) continue;
    Eigen::Vector2d s(0, 0);  // local (xi, eta), Newton on x(s) = target
    for (int it = 0; it < 30; ++it) {
      const Shape sh = shape_at(s[0], s[1]);
      Eigen::Vector2d x = Eigen::Vector2d::Zero();
      Eigen::Matrix2d dx = Eigen::Matrix2d::Zero();
      for (int a = 0; a < 9; ++a) {
        x += sh.N9[a] * xa[a];
        dx.col(0) += sh.dN9[a][0] * xa[a];
        dx.col(1) += sh.dN9[a][1] * xa[a];
      }
      const Eigen::Vector2d step = dx.inverse() * (target - x);
      s += step;
      if (!s.allFinite() || s.cwiseAbs().maxCoeff() > 3) break;
      if (step.norm() < 1e-12) break;
    }
    if (s.allFinite() && s.cwiseAbs().maxCoeff() <= 1 + 1e-9) {
      X_mm = box[0] + 0.5 * (1 + s[0]) * (box[1] - box[0]);
      Y_mm = box[2] + 0.5 * (1 + s[1]) * (box[3] - box[2]);
      return true;
    }
  }
  return false;
}

PoroSolver::PoroSolver(PoroModel model) : impl_(std::make_unique<Impl>(std::move(model))) {}
PoroSolver::~PoroSolver() = default;

const PoroState& PoroSolver::advance_to(double time_s) {
  return impl_->advance_to(time_s);
}
const PoroState& PoroSolver::state() const {
  return impl_->state;
}
const PoroModel& PoroSolver::model() const {
  return impl_->model;
}
int PoroSolver::element_count() const {
  return impl_->grid.element_count();
}

double PoroSolver::pressure_at(double x_mm, double y_mm) const {
  double xi = 0, eta = 0;
  const int e = impl_->grid.locate(x_mm, y_mm, xi, eta);
  if (e < 0) return std::numeric_limits<double>::quiet_NaN();
  const Shape s = shape_at(xi, eta);
  const auto pn = impl_->grid.element_pressure_nodes(e);
  double p = 0;
  for (int c = 0; c < 4; ++c) p += s.N4[c] * impl_->values[impl_->dofs.pressure_offset + pn[c]];
  return p;
}

Eigen::Vector2d PoroSolver::displacement_at(double x_mm, double y_mm) const {
  double xi = 0, eta = 0;
  const int e = impl_->grid.locate(x_mm, y_mm, xi, eta);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (e < 0) return {nan, nan};
  const Shape s = shape_at(xi, eta);
  const auto n = impl_->grid.element_nodes(e);
  Eigen::Vector2d u = Eigen::Vector2d::Zero();
  for (int a = 0; a < 9; ++a)
    u += s.N9[a] * Eigen::Vector2d(impl_->values[2 * n[a]], impl_->values[2 * n[a] + 1]);
  return u;
}

double PoroSolver::volume_ratio_at(double x_mm, double y_mm) const {
  double xi = 0, eta = 0;
  const int e = impl_->grid.locate(x_mm, y_mm, xi, eta);
  if (e < 0) return std::numeric_limits<double>::quiet_NaN();
  return element_volume_ratio(impl_->grid.element_box(e), impl_->model.kinematics,
                              impl_->gather(impl_->values, impl_->element_dofs(e)), xi, eta);
}

PoroSolver::ElementCheck PoroSolver::element_check(int element, const Eigen::VectorXd& local_dofs,
                                                   const Eigen::VectorXd& previous_local_dofs,
                                                   double dt_s) const {
  if (element < 0 || element >= element_count() || local_dofs.size() != kElementDofs ||
      previous_local_dofs.size() != kElementDofs)
    throw PoroError("element_check: element index or dof vector size out of range");
  const ElementPhysics physics{impl_->model.kinematics, impl_->skeleton.get(), &impl_->model.permeability,
                               dt_s};
  ElementVector r;
  ElementMatrix K;
  if (!element_residual(impl_->gauss[element], physics, local_dofs, previous_local_dofs, r, &K))
    throw PoroError("element_check: inadmissible element state");
  return {r, K};
}

}  // namespace tocd::sim::poro

// Displacement-controlled Newton solve of the pin-compression problem (see docs/fe.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>

#include <Eigen/SparseCholesky>
#include <fmt/format.h>

#include "assembly.hpp"
#include "mesh.hpp"
#include "step_output.hpp"
#include "tocd/sim/fe/solve.hpp"
#include "tocd/sim/material/fit.hpp"
#include "tocd/sim/material/hyperelastic.hpp"

namespace tocd::sim::fe {

// The Newton solver is named outside the anonymous namespace: PinCompression's state holds one.
namespace pin_solver {

using Eigen::VectorXd;

/// How far (in pin increments) Newton's step from an indefinite tangent may move an unknown and
/// still be taken (Solver::newton). Newton iterations to 1.5 mm on the default mesh (plane
/// stress, axisymmetric, plane strain): 148, 101, 101 with 2; 149, 103, 101 with 3; 214, 104,
/// 105 with 1; 153, 107, 120 with 5; 172, 113, 111 with the shifted direction alone.
constexpr double kIndefiniteStepLimit = 2;

/// K + shift I, with K's pattern (its diagonal is stored), so the factorisation analysed for K
/// applies to it.
Eigen::SparseMatrix<double> plus_identity(const Eigen::SparseMatrix<double>& K, double shift) {
  Eigen::SparseMatrix<double> out = K;
  for (int i = 0; i < out.rows(); ++i) out.coeffRef(i, i) += shift;
  return out;
}

class Solver {
 public:
  Solver(const FeModel& model, const tocd::sim::material::HyperelasticLaw& law)
      : model_(model), asm_(model, make_reference_mesh(model), law), law_(law) {
    u_ = VectorXd::Zero(asm_.dofs());
    asm_.evaluate(u_, model.thickness_mm, true, ev_);
    ldlt_.analyzePattern(asm_.stiffness());
  }

  /// One load increment to pin displacement d; on failure the state is restored.
  bool increment(double d, double dd_prev, double dd, int& iterations, std::string& why) {
    const VectorXd u0 = u_;
    const std::vector<double> lam0 = asm_.multiplier;
    const Evaluation ev0 = ev_;
    // Penalty from the current (not initial) nodal stiffness of the skin.
    for (std::size_t t = 0; t < asm_.penalty.size(); ++t)
      asm_.penalty[t] = model_.solver.penalty_factor * std::max(ev_.top_stiffness[t], 1e-30);
    // Secant predictor from the last two converged states.
    const double tip = model_.thickness_mm - d;
    bool predicted = false;
    if (dd_prev > 0 && u_prev_.size() == u_.size()) {
      const VectorXd up = u_ + (dd / dd_prev) * (u_ - u_prev_);
      Evaluation e;
      asm_.evaluate(up, tip, true, e);
      if (e.valid) {
        u_ = up;
        ev_ = std::move(e);
        predicted = true;
      }
    }
    if (!predicted) asm_.evaluate(u_, tip, true, ev_);
    const double tol_pen = std::max(model_.solver.penetration_tolerance * d, 1e-9 * model_.thickness_mm);
    bool ok = ev_.valid;
    for (int aug = 0; ok && aug <= model_.solver.max_augmentations; ++aug) {
      ok = newton(tip, dd, iterations, why);
      if (!ok || ev_.max_penetration <= tol_pen || aug == model_.solver.max_augmentations) break;
      for (std::size_t t = 0; t < asm_.multiplier.size(); ++t) asm_.multiplier[t] = ev_.contact_force[t];
      asm_.evaluate(u_, tip, true, ev_);
    }
    if (!ok) {
      u_ = u0;
      asm_.multiplier = lam0;
      ev_ = ev0;
      return false;
    }
    u_prev_ = u0;
    return true;
  }

  const VectorXd& displacement() const { return u_; }
  const Evaluation& evaluation() const { return ev_; }
  Assembly& assembly() { return asm_; }

 private:
  /// Newton iterations at the pin tip's height `tip`, reached by a pin increment `dd`.
  bool newton(double tip, double dd, int& iterations, std::string& why) {
    const double floor = 1e-12 * law_.shear_modulus() * model_.thickness_mm * model_.thickness_mm;
    // Levenberg-Marquardt damping of the tangent, in force per length: zero while Newton's full
    // steps are taken. When the line search keeps only a fraction s of a step, the step ran
    // along a soft direction of K (a near-zero eigenvalue, as where compressed elements at the
    // pin's edge begin to fold) much farther than the energy allows: the next direction is taken
    // with K + damping I, damping raised by the step's Rayleigh quotient times (1/s - 1), which
    // shortens that direction by about s. Full steps lower it tenfold, and clear it once the
    // residual falls tenfold, so the quadratic rate returns. Only the directions change: every
    // step is still weighed on the true energy and convergence on the true residual.
    double damping = 0;
    for (int it = 0; it < model_.solver.max_newton_iterations; ++it) {
      if (ev_.residual_norm <= model_.solver.residual_tolerance * std::max(ev_.internal_force_norm, floor))
        return true;
      ++iterations;
      Eigen::SparseMatrix<double> damped;
      if (damping > 0) damped = plus_identity(asm_.stiffness(), damping);
      const Eigen::SparseMatrix<double>& K = damping > 0 ? damped : asm_.stiffness();
      // Newton's step is trusted where the tangent is positive definite. With a non-positive
      // pivot in its LDL^T the step heads for a saddle as readily as for the minimum: past the
      // fold of a plane-stress section (compressed elements at the pin's edge) it ran so far
      // along a soft direction that the line search kept fractions of 1e-4 of it, increment
      // after increment. It is still taken when it moves no unknown by more than
      // kIndefiniteStepLimit increments: at most increments' start the predictor has pushed
      // nodes into the pin, whose curved surface turns their penalty force as they slide (a
      // negative stiffness), and there Newton's step is a short correction. Otherwise the
      // direction comes from K + tau I, tau as small as makes it positive definite (the
      // modified Newton method): it leads down the energy.
      ldlt_.factorize(K);
      const bool factored = ldlt_.info() == Eigen::Success;
      const bool definite = factored && (ldlt_.vectorD().array() > 0).all();
      VectorXd du;
      if (factored) du = ldlt_.solve(-ev_.residual);
      const bool newton_step = factored && du.allFinite() && ev_.residual.dot(du) < 0 &&
                               (definite || du.lpNorm<Eigen::Infinity>() <= kIndefiniteStepLimit * dd);
      if (!newton_step && !shifted_direction(K, du)) {
        why = "no descent direction";
        return false;
      }
      touch_pin(tip, K, du);
      const double slope = ev_.residual.dot(du);
      const double before = ev_.residual_norm;
      // Line search on the total energy; a trial that inverts an element is never accepted.
      double s = 1;
      bool accepted = false;
      for (int ls = 0; ls < 12 && !accepted; ++ls) {
        VectorXd full = stepped(du, s);
        Evaluation e;
        asm_.evaluate(full, tip, true, e);
        if (e.valid) {
          const double roundoff = 1e-11 * std::abs(ev_.energy);
          if (e.energy <= ev_.energy + 1e-4 * s * slope + roundoff || e.residual_norm < ev_.residual_norm) {
            u_ = full;
            ev_ = std::move(e);
            accepted = true;
            break;
          }
          // Quadratic model of the energy along the direction, kept within [0.1 s, 0.5 s].
          const double denom = 2 * (e.energy - ev_.energy - slope * s);
          const double snew = denom > 0 ? -slope * s * s / denom : 0.5 * s;
          s = std::clamp(snew, 0.1 * s, 0.5 * s);
        } else {
          s *= 0.5;  // an element would invert: shorten the step
        }
      }
      if (!accepted) {
        why = "line search found no admissible step (elements would invert)";
        return false;
      }
      if (s < 0.25) {
        const double rayleigh = -slope / du.squaredNorm();
        damping += rayleigh * (1 / s - 1);
      } else if (s == 1) {
        damping = ev_.residual_norm < 0.1 * before ? 0.0 : 0.1 * damping;
      }
    }
    if (ev_.residual_norm <= model_.solver.residual_tolerance * std::max(ev_.internal_force_norm, floor))
      return true;
    why = fmt::format("no convergence in {} Newton iterations (residual {:.2e} of force scale {:.2e})",
                      model_.solver.max_newton_iterations, ev_.residual_norm, ev_.internal_force_norm);
    return false;
  }

  // The Newton step is taken with the contact of the nodes touching the pin now; a node free
  // of it now but inside it after the step gets no force from the tangent, so the step drives it
  // deep into the pin, where the penalty's energy stops the line search at a tiny fraction of
  // it (iteration after iteration, until the node has crept into contact). Such nodes join the
  // contact for the direction (their penalty force linearised at the present gap, negative
  // while they are apart: the step stops them at the pin's surface), as an active-set Newton
  // does, until the step pushes no further free node in (a few rounds). The direction changes,
  // the equations and their solution do not: the line search still weighs the true energy.
  void touch_pin(double tip, const Eigen::SparseMatrix<double>& K, VectorXd& du) {
    const auto& eq = asm_.equation();
    const auto& top = asm_.top_nodes();
    std::vector<char> joined(top.size(), 0);
    Eigen::SparseMatrix<double> Kc;  // K and the residual with the joined nodes' contact
    VectorXd rc;
    for (int round = 0; round < 4; ++round) {
      const VectorXd after = stepped(du, 1);
      bool more = false;
      for (std::size_t t = 0; t < top.size(); ++t) {
        if (joined[t] || ev_.contact_force[t] > 0 || asm_.pin_contact(t, after, tip).gap >= 0) continue;
        if (Kc.rows() == 0) {
          Kc = K;
          rc = ev_.residual;
        }
        joined[t] = more = true;
        const PinContact now = asm_.pin_contact(t, u_, tip);
        const double k = asm_.penalty[t], p = asm_.multiplier[t] - k * now.gap;
        const int n = top[t];
        for (int i = 0; i < 2; ++i) {
          if (eq[2 * n + i] < 0) continue;
          rc[eq[2 * n + i]] -= p * now.normal[i];
          for (int j = 0; j < 2; ++j)
            if (eq[2 * n + j] >= 0)
              Kc.coeffRef(eq[2 * n + i], eq[2 * n + j]) += k * now.normal[i] * now.normal[j];
        }
      }
      if (!more) break;
      ldlt_.factorize(Kc);
      if (ldlt_.info() != Eigen::Success) break;
      const VectorXd trial = ldlt_.solve(-rc);
      if (!trial.allFinite() || ev_.residual.dot(trial) >= 0) break;  // not a descent direction
      du = trial;
    }
  }

  /// The displacements (all dofs) a fraction s of the step du (free dofs) leads to.
  VectorXd stepped(const VectorXd& du, double s) const {
    const auto& eq = asm_.equation();
    VectorXd out(u_.size());
    for (int d = 0; d < asm_.dofs(); ++d) out[d] = eq[d] >= 0 ? u_[d] + s * du[eq[d]] : u_[d];
    return out;
  }

  // The smallest tau = 10^k x 1e-8 x the largest diagonal entry (k >= 0) making K + tau I positive
  // definite (LDL^T succeeds with every pivot positive), searched upwards from a hundredth of the
  // last one found (neighbouring iterations need about the same shift); false when none up to the
  // diagonal's size does.
  bool shifted_direction(const Eigen::SparseMatrix<double>& K, VectorXd& du) {
    const double scale = K.diagonal().cwiseAbs().maxCoeff();
    if (!(scale > 0) || !std::isfinite(scale)) return false;
    for (double tau = std::max(1e-8 * scale, 0.01 * last_shift_); tau <= scale; tau *= 10) {
      ldlt_.factorize(plus_identity(K, tau));
      if (ldlt_.info() != Eigen::Success || !(ldlt_.vectorD().array() > 0).all()) continue;
      du = ldlt_.solve(-ev_.residual);
      if (du.allFinite() && ev_.residual.dot(du) < 0) {
        last_shift_ = tau;
        return true;
      }
    }
    return false;
  }

  const FeModel& model_;
  Assembly asm_;
  const tocd::sim::material::HyperelasticLaw& law_;
  VectorXd u_, u_prev_;
  Evaluation ev_;
  double last_shift_ = 0;  ///< tau of the last shifted direction
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
};

}  // namespace pin_solver

namespace {

FeModel validated(FeModel model) {
  model.validate();
  return model;
}

// The displacements an advance is asked for, against the model's thickness (validated already).
void check_displacements(const FeModel& model, const std::vector<double>& d) {
  if (d.empty()) throw FeError("FE solve: no displacements requested");
  for (std::size_t k = 0; k < d.size(); ++k) {
    if (!(d[k] > 0) || !std::isfinite(d[k]))
      throw FeError(fmt::format("FE solve: displacement {} mm must be positive", d[k]));
    if (k > 0 && !(d[k] > d[k - 1]))
      throw FeError(
          fmt::format("FE solve: displacements must be ascending ({} mm after {} mm)", d[k], d[k - 1]));
    if (d[k] >= model.thickness_mm)
      throw FeError(fmt::format("FE solve: displacement {} mm reaches or passes the slab (thickness {} mm)",
                                d[k], model.thickness_mm));
  }
}

void check_stability(const tocd::sim::material::OgdenLaw& law, const FeModel& model, double deepest_mm) {
  // Drucker stability over the stretches the requested compression can reach (and their
  // inverses, met laterally): an unstable law would give a meaningless answer.
  const double lmin = std::clamp(1 - 2 * deepest_mm / model.thickness_mm, 0.15, 0.9);
  const auto stab = tocd::sim::material::check_stability(law, lmin, 1 / lmin);
  if (!stab.stable)
    throw FeError(fmt::format(
        "FE solve: the material is unstable (Drucker) within the stretch range [{:.3g}, {:.3g}]: {}", lmin,
        1 / lmin, stab.first_failure));
}

}  // namespace

// The model and law live here, at fixed addresses, because the solver keeps references to them.
// The model is validated first, before the law or the solver's mesh is made from it.
struct PinCompression::State {
  explicit State(FeModel m) : model(validated(std::move(m))), law(model.material), solver(model, law) {}
  FeModel model;
  tocd::sim::material::OgdenLaw law;
  pin_solver::Solver solver;
  double d = 0, step = 0, dd_prev = 0;  ///< where the path is, the next increment, the last one
  std::vector<double> path;
  bool usable = true;
};

PinCompression::PinCompression(FeModel model) : state_(std::make_unique<State>(std::move(model))) {}
PinCompression::~PinCompression() = default;
PinCompression::PinCompression(PinCompression&&) noexcept = default;
PinCompression& PinCompression::operator=(PinCompression&&) noexcept = default;

const std::vector<double>& PinCompression::path_mm() const {
  return state_->path;
}

bool PinCompression::usable() const {
  return state_->usable;
}

FeResult PinCompression::advance(const std::vector<double>& displacements_mm,
                                 const std::function<void(double)>& on_increment) {
  State& st = *state_;
  if (!st.usable) throw FeError("FE solve: this compression stopped earlier and cannot go on");
  check_displacements(st.model, displacements_mm);
  if (!st.path.empty() && !(displacements_mm.front() > st.path.back()))
    throw FeError(fmt::format("FE solve: displacement {} mm does not go on from {} mm, where the path is",
                              displacements_mm.front(), st.path.back()));
  const auto t0 = std::chrono::steady_clock::now();
  check_stability(st.law, st.model, displacements_mm.back());

  FeResult res;
  res.model = st.model;
  const auto& sv = st.model.solver;
  if (st.path.empty()) st.step = std::min(sv.initial_step_mm, displacements_mm.front());
  double& d = st.d;
  int iters_since = 0, incs_since = 0;
  std::size_t next = 0;
  st.usable = false;  // until this advance reaches its last displacement
  while (next < displacements_mm.size()) {
    const double target = displacements_mm[next];
    double dd = std::min(st.step, target - d);
    if (target - d - dd < 0.25 * dd) dd = target - d;  // no sliver increment before a target
    int iters = 0;
    std::string why;
    const bool ok = st.solver.increment(d + dd, st.dd_prev, dd, iters, why);
    iters_since += iters;
    res.total_newton_iterations += iters;
    if (!ok) {
      st.step = 0.5 * dd;
      if (st.step < sv.min_step_mm) {
        res.complete = false;
        res.stop_reason = fmt::format(
            "stopped at {:.4g} mm (last converged; {:.4g} mm requested): {} at {:.4g} mm with the smallest "
            "increment",
            d, target, why, d + dd);
        break;
      }
      continue;
    }
    d = (dd == target - d) ? target : d + dd;
    st.dd_prev = dd;
    ++incs_since;
    ++res.total_load_increments;
    if (on_increment) on_increment(d);
    if (iters <= 5)
      st.step = std::min(sv.max_step_mm, 1.5 * dd);
    else if (iters >= 12)
      st.step = std::max(sv.min_step_mm, 0.6 * dd);
    else
      st.step = dd;
    if (d == target) {
      res.steps.push_back(make_step_result(st.model, st.law, st.solver.assembly(), st.solver.displacement(),
                                           st.solver.evaluation(), d));
      res.steps.back().newton_iterations = iters_since;
      res.steps.back().load_increments = incs_since;
      iters_since = incs_since = 0;
      st.path.push_back(d);
      ++next;
    }
  }
  res.complete = next == displacements_mm.size();
  st.usable = res.complete;
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

FeResult solve(const FeModel& model, const std::vector<double>& displacements_mm) {
  return solve(model, displacements_mm, {});
}

FeResult solve(const FeModel& model, const std::vector<double>& displacements_mm,
               const std::function<void(double)>& on_increment) {
  const auto t0 = std::chrono::steady_clock::now();
  FeResult res = PinCompression(model).advance(displacements_mm, on_increment);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace tocd::sim::fe

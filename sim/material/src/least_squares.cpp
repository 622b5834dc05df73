#include "tocd/sim/material/least_squares.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "tocd/sim/material/ogden.hpp"

namespace tocd::sim::material {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// Standard normal quantile (Acklam's rational approximation, relative error < 1.2e-9).
double normal_quantile(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  const double lo = 0.02425;
  if (p < lo) {
    const double q = std::sqrt(-2 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  if (p > 1 - lo) return -normal_quantile(1 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
}

// The covariance s^2 (J^T J)^+ through the SVD of J: directions the data do not constrain
// (singular values below 1e-10 of the largest) get an infinite variance instead of a
// meaningless huge number.
MatrixXd covariance_of(const MatrixXd& J, double s2) {
  const Eigen::JacobiSVD<MatrixXd> svd(J, Eigen::ComputeThinV);
  const VectorXd& sv = svd.singularValues();
  const MatrixXd& V = svd.matrixV();
  const double cut = 1e-10 * (sv.size() ? sv[0] : 0.0);
  MatrixXd C = MatrixXd::Zero(J.cols(), J.cols());
  for (int k = 0; k < sv.size(); ++k) {
    if (sv[k] > cut) {
      C += V.col(k) * V.col(k).transpose() * (s2 / (sv[k] * sv[k]));
    } else {
      for (int i = 0; i < J.cols(); ++i)
        if (std::abs(V(i, k)) > 1e-6) C(i, i) = std::numeric_limits<double>::infinity();
    }
  }
  return C;
}

}  // namespace

double student_t_quantile(double confidence, double dof) {
  if (!(confidence > 0 && confidence < 1) || !(dof > 0))
    throw MaterialError(
        fmt::format("t quantile: confidence {} or degrees of freedom {} out of range", confidence, dof));
  const double z = normal_quantile(0.5 + confidence / 2), z2 = z * z;
  // Cornish-Fisher expansion of the t quantile in 1/dof (Abramowitz & Stegun 26.7.5).
  const double g1 = (z2 + 1) * z / 4;
  const double g2 = ((5 * z2 + 16) * z2 + 3) * z / 96;
  const double g3 = (((3 * z2 + 19) * z2 + 17) * z2 - 15) * z / 384;
  const double g4 = ((((79 * z2 + 776) * z2 + 1482) * z2 - 1920) * z2 - 945) * z / 92160;
  const double v = dof;
  return z + g1 / v + g2 / (v * v) + g3 / (v * v * v) + g4 / (v * v * v * v);
}

LeastSquaresResult levenberg_marquardt(const LeastSquaresProblem& pr, const LeastSquaresOptions& opt) {
  const int n = static_cast<int>(pr.start.size());
  if (n == 0 || pr.difference_step.size() != n || static_cast<int>(pr.names.size()) != n)
    throw MaterialError("least squares: parameters, names and difference steps differ in number");
  LeastSquaresResult out;
  auto evaluate = [&](const VectorXd& theta) {
    ++out.evaluations;
    auto r = pr.residuals(theta);
    if (r && !r->allFinite()) r.reset();
    return r;
  };
  VectorXd theta = pr.start;
  auto r0 = evaluate(theta);
  if (!r0) throw MaterialError("least squares: the model cannot be evaluated at the starting parameters");
  VectorXd r = *r0;
  if (r.size() <= n)
    throw MaterialError(
        fmt::format("least squares: {} data points for {} parameters (need more points)", r.size(), n));

  auto jacobian = [&](const VectorXd& at, const VectorXd& r_at) {
    MatrixXd J(r_at.size(), n);
    for (int j = 0; j < n; ++j) {
      double h = pr.difference_step[j];
      VectorXd tp = at;
      tp[j] += h;
      auto rp = evaluate(tp);
      if (!rp) {  // outside the admissible range on this side: difference backwards
        h = -h;
        tp[j] = at[j] + h;
        rp = evaluate(tp);
      }
      J.col(j) = rp ? VectorXd((*rp - r_at) / h) : VectorXd::Zero(r_at.size());
    }
    return J;
  };

  double cost = r.squaredNorm(), damping = 1e-3;
  MatrixXd J = jacobian(theta, r);
  out.stop_reason = "iteration limit";
  for (out.iterations = 0; out.iterations < opt.max_iterations;) {
    const MatrixXd A = J.transpose() * J;
    const VectorXd g = J.transpose() * r;
    bool accepted = false;
    double gain = 0;
    for (int tries = 0; tries < 12 && !accepted; ++tries) {
      MatrixXd Ad = A;
      Ad.diagonal() += damping * A.diagonal().cwiseMax(1e-30);
      const VectorXd step = Ad.ldlt().solve(-g);
      if (!step.allFinite()) break;
      const auto rt = evaluate(theta + step);
      if (rt && rt->squaredNorm() < cost) {
        gain = (cost - rt->squaredNorm()) / cost;
        theta += step;
        r = *rt;
        cost = r.squaredNorm();
        damping = std::max(damping / 4, 1e-9);
        accepted = true;
      } else {
        damping *= 6;
      }
    }
    if (!accepted) {
      out.converged = true;  // no downhill step at any damping: a local minimum to FD accuracy
      out.stop_reason = "no further descent";
      break;
    }
    ++out.iterations;
    if (opt.progress) opt.progress(out.iterations, cost, out.evaluations);
    J = jacobian(theta, r);
    if (gain < opt.cost_tolerance) {
      out.converged = true;
      out.stop_reason = "cost change below tolerance";
      break;
    }
  }
  out.theta = theta;
  out.residuals = r;
  out.cost = cost;
  out.jacobian = J;
  const double dof = static_cast<double>(r.size() - n);
  out.residual_variance = cost / dof;
  out.covariance = covariance_of(J, out.residual_variance);
  out.t_quantile = student_t_quantile(opt.confidence, dof);
  out.standard_error = out.covariance.diagonal().cwiseSqrt();
  out.interval_half_width = out.t_quantile * out.standard_error;
  return out;
}

}  // namespace tocd::sim::material

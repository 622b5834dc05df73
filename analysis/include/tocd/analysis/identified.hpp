#pragma once

// A parameter identified from a run, reported with what the run says about it: its 95 %
// interval, whether the run determines it at all, and how it moves with the others.

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

namespace tocd::analysis {

/// What a parameter can be before any run is seen. A parameter counts as determined when its
/// 95 % interval is narrower than a quarter of this range (on a log scale for log-scale
/// parameters): the run then says clearly more than the range did. Otherwise it is reported
/// as not determined, with its interval for what it is worth, never as a number to believe.
struct PlausibleRange {
  double lo = 0, hi = 1;
  bool log_scale = false;  ///< positive quantities known to within factors: intervals on ln
};

struct IdentifiedParameter {
  std::string name;         ///< e.g. "stiffness_scale", "g1", "tau1_s"
  std::string description;  ///< one line for a lab user
  double value = 0;
  double se = 0;          ///< standard error (infinite when the run carries no information on it)
  double lo = 0, hi = 0;  ///< 95 % interval
  PlausibleRange range;
  bool determined = false;
  std::string why_not;  ///< when not determined: what the run lacks
  /// How lo and hi were found: "wald" (value +- z se from the covariance) or "profile" (where
  /// the least-squares cost, minimised over every other parameter, has risen by z^2 residual
  /// variances: the interval follows the valley the data leave, however curved).
  std::string interval = "wald";
};

/// Parameters with their covariance, as estimated by a least-squares fit.
struct ParameterReport {
  std::vector<IdentifiedParameter> parameters;
  std::vector<std::vector<double>> correlation;  ///< between the parameters, in their order
  double residual_rms = 0;
  double noise_sigma = 0;         ///< noise standard deviation the intervals rest on
  double autocorrelation = 0;     ///< lag-1 correlation of consecutive residuals
  double variance_inflation = 1;  ///< (1 + rho) / (1 - rho) for rho > 0: fewer independent readings
  std::size_t observations = 0;
  int iterations = 0;
  bool converged = false;

  const IdentifiedParameter& at(const std::string& name) const;  ///< throws tocd::Error if absent
};

/// Fills se, lo, hi, determined and the correlation from a covariance matrix of the parameters
/// (natural scale, in report order). A non-finite or non-positive variance gives an infinite
/// se and "the run carries no information on it"; an interval of quantile z x se (z = 1.96),
/// on ln(value) for log-scale parameters.
void apply_covariance(ParameterReport& report, const Eigen::MatrixXd& covariance,
                      double z = 1.959963984540054);

/// Marks every parameter the report counts as determined as not determined, for `why`: a reason
/// that holds for the whole fit (its estimate is not a minimum of the cost; its intervals are
/// not calibrated). Values and intervals stay, for what they are worth; parameters already not
/// determined keep their own reason.
void withhold_determination(ParameterReport& report, const std::string& why);

/// The profile of a least-squares cost in one parameter: its lowest residual sum of squares
/// with that parameter held at `value` and every other parameter free, less the fit's minimum,
/// in units of the residual variance (sigma^2 times the variance inflation). NaN where no fit
/// could be made at that value.
using CostRise = std::function<double(double value)>;

/// Replaces a parameter's interval by its profile-likelihood interval: the two values where
/// `rise` reaches z^2 on either side of the estimate (about 3.84 for 95 %). Wald intervals of a
/// nearly degenerate fit (a curved valley, as the stiffness, overstress share and relaxation
/// time of a run with short holds leave) misstate their coverage; profile intervals keep it
/// (Venzon and Moolgavkar 1988; Bates and Watts 1988, ch. 6). The search starts at the Wald
/// ends and walks by secant steps on sqrt(rise) (on ln for log-scale parameters), then closes
/// in on the crossing by regula falsi. Where the profile stays below z^2 out to the plausible
/// range's end, the interval ends there (a share that may be 0, a time that may be anything
/// longer). The determination rule (PlausibleRange) applies to the profile interval; se and
/// the correlations stay those of the covariance.
void apply_profile(IdentifiedParameter& parameter, const CostRise& rise, double z = 1.959963984540054);

/// Widens a profile interval (apply_profile) to hold every point of `scan`, the profile's rise
/// at grid values over the plausible range (value, rise; in order of value), where the rise is
/// below z^2: a profile with a second valley apart from the estimate's. Each widened end runs
/// to the grid value beyond the last such point (or the range's end, which leaves that side
/// open), and the determination rule is applied again.
void widen_to_profile_hull(IdentifiedParameter& parameter, const std::vector<std::pair<double, double>>& scan,
                           double z = 1.959963984540054);

/// A point on the floor of a fit's valley in its nonlinear parameters, for the parameters in
/// which the model is linear (solved exactly there): the residual sum of squares at the point,
/// the linear parameters' values and, for each, how fast the sum rises with it alone (the
/// diagonal of (B^T B)^-1 of the weighted basis B: the sum grows by (x - value)^2 / that).
struct ValleyPoint {
  double cost = 0;
  std::vector<double> linear, conditional_variance;
};

/// Widens the interval of linear parameter `index` (of the ValleyPoints) to its profile over the
/// valley: at each point whose rise is below z^2 the values whose cost, with the nonlinear
/// parameters held there, rises by less than z^2 residual variances; the interval becomes the
/// hull of those and the Wald interval. A Wald interval treats the nonlinear parameters as
/// known to their standard errors; where they are not (a small delayed share, whose time may
/// be anything from seconds to minutes), the linear ones shift with them far beyond it. The
/// determination rule applies again.
void widen_over_valley(IdentifiedParameter& parameter, std::size_t index,
                       const std::vector<ValleyPoint>& valley, double rss_min, double residual_variance,
                       double z = 1.959963984540054);

/// The covariance of a least-squares estimate: sigma^2 (J^T J)^-1, J the Jacobian of the model
/// at the rows, in natural parameters. Columns are scaled to unit norm before the inverse and
/// directions the data do not see (eigenvalues below 1e-12 of the largest) left out: their
/// parameters get an infinite variance.
Eigen::MatrixXd least_squares_covariance(const Eigen::MatrixXd& jacobian, double sigma2);

/// Sets report.autocorrelation (the lag-1 autocorrelation of `residuals`, over consecutive
/// pairs within each of `segments`: index ranges [first, last] into them) and the
/// variance inflation it implies: (1 + rho) / (1 - rho) for rho > 0 (readings that follow each
/// other carry less independent information), 1 otherwise.
void set_autocorrelation(ParameterReport& report, const Eigen::VectorXd& residuals,
                         const std::vector<std::pair<std::size_t, std::size_t>>& segments);

nlohmann::json to_json(const ParameterReport& report);

}  // namespace tocd::analysis

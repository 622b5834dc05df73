// The identified sample as text (identify_report.hpp).
#include "identify_report.hpp"

#include <cmath>
#include <string>

#include <fmt/format.h>

namespace tocd::cli {

std::string interval_text(double lo, double hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) return "none";
  return fmt::format("[{:.5g}, {:.5g}]", lo, hi);
}

namespace {

void print_parameters(std::ostream& out, const analysis::ParameterReport& rep) {
  out << fmt::format("  {:<24} {:>11}  {:<26} {}\n", "parameter", "value", "95 % interval", "determined");
  for (const auto& p : rep.parameters)
    out << fmt::format("  {:<24} {:>11.5g}  {:<26} {}\n", p.name, p.value, interval_text(p.lo, p.hi),
                       p.determined ? "yes" : "no: " + p.why_not);
  for (std::size_t i = 0; i < rep.parameters.size(); ++i)
    for (std::size_t j = i + 1; j < rep.parameters.size(); ++j)
      if (std::abs(rep.correlation[i][j]) >= 0.9)
        out << fmt::format(
            "  correlated: {} and {} ({:+.3f}): the run tells their combination better than each\n",
            rep.parameters[i].name, rep.parameters[j].name, rep.correlation[i][j]);
}

}  // namespace

void print_identification(std::ostream& out, const analysis::SampleIdentification& id) {
  const auto& m = id.mechanics;
  out << fmt::format("Identified sample of run {} ({} mm thick)\n", id.run_id, id.thickness_mm);
  out << fmt::format(
      "Mechanics: QLV on the FE of the published Ogden skin law ({} tester readings in {} holds)\n",
      m.report.observations, m.holds.size());
  print_parameters(out, m.report);
  out << fmt::format("  load noise {:.4g} N, residual autocorrelation {:.3f}{}\n", m.report.noise_sigma,
                     m.report.autocorrelation, m.report.converged ? "" : "; the fit did NOT converge");
  out << fmt::format("  {:>4} {:>8} {:>12} {:>12} {:>12}\n", "step", "d_mm", "measured_N", "fitted_N",
                     "rms_N");
  for (const auto& h : m.holds)
    out << fmt::format("  {:>4} {:>8.3f} {:>12.5f} {:>12.5f} {:>12.2e}\n", h.step_index + 1,
                       h.displacement_mm, h.measured_N, h.fitted_N, h.residual_rms_N);
  if (id.clearing) {
    const auto& c = *id.clearing;
    out << fmt::format(
        "Clearing over time: T = (1 - f) T_eq(d) + f T_eq(drained d) ({} meter readings in the holds)\n",
        c.report.observations);
    print_parameters(out, c.report);
    out << fmt::format("  transmission noise {:.4g}, residual autocorrelation {:.3f}\n", c.report.noise_sigma,
                       c.report.autocorrelation);
  }
  if (!id.optics_not_identified.empty())
    out << "Clearing optics: not identified (" << id.optics_not_identified << ")\n";
  if (id.optics) {
    const auto& o = *id.optics;
    out << fmt::format(
        "Clearing optics: strain-graded model on each held step's FE geometry, Monte Carlo "
        "(chi2 {:.2f} for {} degrees of freedom; {} Monte Carlo runs{})\n",
        o.chi2, o.dof, o.monte_carlo_runs,
        o.report.converged ? ""
                           : fmt::format("; the fit did NOT converge in {} trials", o.report.iterations));
    print_parameters(out, o.report);
    out << fmt::format("  {:>4} {:>8} {:>11} {:>9} {:>12} {:>9}\n", "step", "d_mm", "measured_T", "+-",
                       "identified_T", "+-");
    for (const auto& s : o.steps)
      out << fmt::format("  {:>4} {:>8.3f} {:>11.5f} {:>9.5f} {:>12.5f} {:>9.5f}\n", s.step_index + 1,
                         s.displacement_mm, s.measured_T, s.measured_T_se, s.predicted_T, s.predicted_T_se);
  }
}

}  // namespace tocd::cli

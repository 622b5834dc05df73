#include "tocd/sim/material/loading_modes.hpp"

#include <cmath>

#include <fmt/format.h>

#include "tocd/core/enum_names.hpp"

namespace tocd::sim::material {

namespace {
constexpr std::array<EnumName<LoadingMode>, 3> kLoadingModeNames{
    {{LoadingMode::uniaxial, "uniaxial"},
     {LoadingMode::equibiaxial, "equibiaxial"},
     {LoadingMode::simple_shear, "simple-shear"}}};
}  // namespace

LoadingMode parse_loading_mode(const std::string& name) {
  if (name == "shear") return LoadingMode::simple_shear;  // the short spelling, also accepted
  if (const auto m = value_of(kLoadingModeNames, name)) return *m;
  throw MaterialError(fmt::format("unknown loading mode '{}' (use {})", name, name_list(kLoadingModeNames)));
}

std::string to_string(LoadingMode mode) {
  return std::string(name_of(kLoadingModeNames, mode, "?"));
}

double ogden_nominal_stress(const OgdenParameters& p, LoadingMode mode, double x) {
  if (!std::isfinite(x)) throw MaterialError("closed-form stress: the stretch or shear is not a number");
  if (mode != LoadingMode::simple_shear && !(x > 0))
    throw MaterialError(fmt::format("closed-form {} stress: stretch {} must be > 0", to_string(mode), x));
  // Principal Cauchy stress differences of the incompressible law: the pressure cancels.
  auto sigma = [&](double l) {
    double s = 0;
    for (std::size_t i = 0; i < p.mu.size(); ++i) s += 2 * p.mu[i] / p.alpha[i] * std::pow(l, p.alpha[i]);
    return s;
  };
  switch (mode) {
    case LoadingMode::uniaxial:
      return (sigma(x) - sigma(1 / std::sqrt(x))) / x;
    case LoadingMode::equibiaxial:
      return (sigma(x) - sigma(1 / (x * x))) / x;
    case LoadingMode::simple_shear: {
      const double root = std::sqrt(1 + x * x / 4);
      const double l1 = root + x / 2, l2 = root - x / 2;
      return (sigma(l1) - sigma(l2)) / (l1 + l2);
    }
  }
  return 0;
}

}  // namespace tocd::sim::material

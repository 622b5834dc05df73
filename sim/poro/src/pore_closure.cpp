#include "pore_closure.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace tocd::sim::poro {

namespace mat = tocd::sim::material;

mat::VolumetricResponse PoreClosure::at(double J, double phi0, double bulk_modulus) const {
  const double ds_dJ = 1 / (1 - phi0), s = (J - phi0) * ds_dJ;
  if (!(onset > 0) || s >= onset) return {};
  if (!(s > 0)) {  // pores closed or overrun: no admissible energy
    const double inf = std::numeric_limits<double>::infinity();
    return {inf, -inf, inf};
  }
  const double e = s - onset, l = std::log(s / onset), K = modulus_factor * bulk_modulus;
  const double b = -e * e * l;
  const double db = -2 * e * l - e * e / s;
  const double d2b = -2 * l - 4 * e / s + e * e / (s * s);
  return {K * b, K * db * ds_dJ, K * d2b * ds_dJ * ds_dJ};
}

PoreClosingSkeleton::PoreClosingSkeleton(std::unique_ptr<mat::HyperelasticLaw> skeleton, PoreClosure closure,
                                         double solid_fraction)
    : skeleton_(std::move(skeleton)), closure_(closure), phi0_(solid_fraction) {}

mat::PrincipalResponse PoreClosingSkeleton::isochoric(const mat::Vec3& lambda) const {
  return skeleton_->isochoric(lambda);
}

mat::VolumetricResponse PoreClosingSkeleton::volumetric(double J) const {
  mat::VolumetricResponse v = skeleton_->volumetric(J);
  const mat::VolumetricResponse c = closure_.at(J, phi0_, skeleton_->bulk_modulus());
  v.U += c.U;
  v.dU += c.dU;
  v.d2U += c.d2U;
  return v;
}

std::string PoreClosingSkeleton::describe() const {
  return fmt::format("{} + pore closure (onset {} of the pore volume, {} x K)", skeleton_->describe(),
                     closure_.onset, closure_.modulus_factor);
}

double PoreClosingSkeleton::shear_modulus() const {
  return skeleton_->shear_modulus();
}

double PoreClosingSkeleton::bulk_modulus() const {
  return skeleton_->bulk_modulus();  // the closure term is zero near J = 1
}

std::unique_ptr<mat::HyperelasticLaw> make_skeleton_law(const PoroModel& model) {
  auto law = mat::make_ogden(model.skeleton);
  if (!(model.pore_closure.onset > 0)) return law;
  return std::make_unique<PoreClosingSkeleton>(std::move(law), model.pore_closure,
                                               model.permeability.solid_fraction);
}

}  // namespace tocd::sim::poro

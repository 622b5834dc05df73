#pragma once

#include <memory>

#include "tocd/sim/material/hyperelastic.hpp"
#include "tocd/sim/poro/model.hpp"

namespace tocd::sim::poro {

/// The drained skeleton's law with the pore-closure term of PoreClosure (model.hpp) added to
/// its volumetric part; the isochoric part is the skeleton's.
class PoreClosingSkeleton final : public tocd::sim::material::HyperelasticLaw {
 public:
  PoreClosingSkeleton(std::unique_ptr<tocd::sim::material::HyperelasticLaw> skeleton, PoreClosure closure,
                      double solid_fraction);

  tocd::sim::material::PrincipalResponse isochoric(const tocd::sim::material::Vec3& lambda) const override;
  tocd::sim::material::VolumetricResponse volumetric(double J) const override;
  std::string describe() const override;
  double shear_modulus() const override;
  double bulk_modulus() const override;

 private:
  std::unique_ptr<tocd::sim::material::HyperelasticLaw> skeleton_;
  PoreClosure closure_;
  double phi0_;
};

/// The skeleton law of a model: its Ogden law, with the pore-closure term unless it is off.
std::unique_ptr<tocd::sim::material::HyperelasticLaw> make_skeleton_law(const PoroModel& model);

}  // namespace tocd::sim::poro

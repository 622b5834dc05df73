#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tocd/sim/material/ogden.hpp"

namespace tocd::sim::material {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

/// Response of a strain energy written in principal stretches, with x_a = ln(lambda_a):
/// psi, the principal Kirchhoff stresses tau_a = d psi / d x_a and their derivatives
/// dtau(a, b) = d tau_a / d x_b (symmetric).
struct PrincipalResponse {
  double psi = 0;
  Vec3 tau = Vec3::Zero();
  Mat3 dtau = Mat3::Zero();
};

/// Volumetric part U(J) and its first two derivatives.
struct VolumetricResponse {
  double U = 0, dU = 0, d2U = 0;
};

/// An isotropic hyperelastic law in the decoupled (Abaqus) form
///   W(F) = W_iso(lb1, lb2, lb3) + U(J),   lb_a = J^(-1/3) lambda_a.
/// Every law here is written in principal stretches; coincident stretches are handled where
/// the tensor quantities are assembled (see tensor.hpp).
class HyperelasticLaw {
 public:
  virtual ~HyperelasticLaw() = default;
  /// W_iso and its derivatives with respect to x_a = ln(lambda_a) of the *full* stretches
  /// (the isochoric projection is inside): sum_a tau_a = 0 and dtau * (1,1,1) = 0.
  virtual PrincipalResponse isochoric(const Vec3& lambda) const = 0;
  virtual VolumetricResponse volumetric(double J) const = 0;
  virtual std::string describe() const = 0;
  /// Small-strain shear and bulk moduli [MPa] (bulk = +inf when there is no volumetric term).
  virtual double shear_modulus() const = 0;
  virtual double bulk_modulus() const = 0;

  /// Total response (isochoric + volumetric) in principal log-stretch coordinates:
  /// tau_a += J U'(J), dtau(a, b) += J U' + J^2 U''.
  PrincipalResponse total(const Vec3& lambda) const;

  /// Plane stress: the stretch lambda_3 at which the total tau_3 vanishes with lambda_1 and
  /// lambda_2 held. Newton in x_3 = ln lambda_3 from the incompressible guess, steps capped at
  /// 0.5, until a step is below 1e-13 (that step taken); 0 when it does not converge
  /// within 50 steps or tau_3 stops rising with x_3 (the law has lost its stability there).
  /// This evaluates total() at each step; a law may solve the same equation cheaper (the
  /// answer then agrees within rounding).
  virtual double plane_stress_stretch(double lambda1, double lambda2) const;
};

/// Abaqus volumetric term sum_i (1/D_i)(J - 1)^(2i) (D_i = 0: term absent).
VolumetricResponse abaqus_volumetric(const std::vector<double>& D, double J);

/// The Ogden law of OgdenParameters (validated on construction).
class OgdenLaw final : public HyperelasticLaw {
 public:
  explicit OgdenLaw(OgdenParameters p);
  PrincipalResponse isochoric(const Vec3& lambda) const override;
  VolumetricResponse volumetric(double J) const override;
  std::string describe() const override;
  double shear_modulus() const override;
  double bulk_modulus() const override;
  /// The same Newton steps, each from one exponential per term instead of the full response.
  double plane_stress_stretch(double lambda1, double lambda2) const override;
  const OgdenParameters& parameters() const { return p_; }

 private:
  OgdenParameters p_;
};

/// Abaqus polynomial-family laws in the invariants of the isochoric left Cauchy-Green tensor:
/// Neo-Hookean C10 (I1b - 3); Mooney-Rivlin C10 (I1b - 3) + C01 (I2b - 3);
/// Yeoh C10 (I1b - 3) + C20 (I1b - 3)^2 + C30 (I1b - 3)^3; each plus sum (1/D_i)(J-1)^(2i).
class ReducedPolynomialLaw final : public HyperelasticLaw {
 public:
  /// c1[k] multiplies (I1b - 3)^(k+1); c01 multiplies (I2b - 3).
  ReducedPolynomialLaw(std::string name, std::vector<double> c1, double c01, std::vector<double> D);
  PrincipalResponse isochoric(const Vec3& lambda) const override;
  VolumetricResponse volumetric(double J) const override;
  std::string describe() const override;
  double shear_modulus() const override;
  double bulk_modulus() const override;

 private:
  std::string name_;
  std::vector<double> c1_;
  double c01_;
  std::vector<double> D_;
};

std::unique_ptr<HyperelasticLaw> make_ogden(const OgdenParameters& p);
std::unique_ptr<HyperelasticLaw> make_neo_hookean(double C10, double D1);
std::unique_ptr<HyperelasticLaw> make_mooney_rivlin(double C10, double C01, double D1);
std::unique_ptr<HyperelasticLaw> make_yeoh(double C10, double C20, double C30, double D1);

}  // namespace tocd::sim::material

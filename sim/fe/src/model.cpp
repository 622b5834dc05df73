#include "tocd/sim/fe/model.hpp"

#include <cmath>

#include <fmt/format.h>

#include "tocd/core/enum_names.hpp"

namespace tocd::sim::fe {

namespace {
constexpr std::array<EnumName<Kinematics>, 3> kKinematicsNames{{{Kinematics::axisymmetric, "axisymmetric"},
                                                                {Kinematics::plane_strain, "plane-strain"},
                                                                {Kinematics::plane_stress, "plane-stress"}}};
}  // namespace

Kinematics parse_kinematics(const std::string& s) {
  if (s == "axi") return Kinematics::axisymmetric;  // the short spelling, also accepted
  if (const auto k = value_of(kKinematicsNames, s)) return *k;
  throw FeError(
      fmt::format("unknown kinematics '{}' (use {}; axi for short)", s, name_list(kKinematicsNames)));
}

std::string to_string(Kinematics k) {
  return std::string(name_of(kKinematicsNames, k, "?"));
}

namespace {
constexpr std::array<EnumName<Bottom>, 2> kBottomNames{
    {{Bottom::bonded, "bonded"}, {Bottom::sliding, "sliding"}}};
}  // namespace

Bottom parse_bottom(const std::string& s) {
  if (const auto b = value_of(kBottomNames, s)) return *b;
  throw FeError(fmt::format("unknown bottom condition '{}' (use {})", s, name_list(kBottomNames)));
}

std::string to_string(Bottom b) {
  return std::string(name_of(kBottomNames, b, "?"));
}

FeModel FeModel::published_default() {
  FeModel m;
  m.material = tocd::sim::material::OgdenParameters::published_skin();
  return m;
}

void FeModel::validate() const {
  auto positive = [](const char* name, double v) {
    if (!(v > 0) || !std::isfinite(v))
      throw FeError(fmt::format("FE model: {} = {} must be positive", name, v));
  };
  positive("thickness_mm", thickness_mm);
  positive("outer_radius_mm", outer_radius_mm);
  positive("pin_radius_mm", pin_radius_mm);
  positive("mesh_refinement", mesh_refinement);
  positive("depth_mm", depth_mm);
  if (!(compressed_log_strain < 0))
    throw FeError(
        fmt::format("FE model: compressed_log_strain = {} must be negative", compressed_log_strain));
  if (mesh_refinement > 16)
    throw FeError(fmt::format("FE model: mesh_refinement = {} is above 16", mesh_refinement));
  if (pin_radius_mm >= outer_radius_mm)
    throw FeError(fmt::format("FE model: pin radius {} mm must be smaller than the outer radius {} mm",
                              pin_radius_mm, outer_radius_mm));
  try {
    material.validate();
  } catch (const tocd::Error& e) {
    throw FeError(fmt::format("FE model: {}", e.what()));
  }
  if (material.D.empty() || material.D[0] <= 0)
    throw FeError(
        "FE model: the material needs a bulk modulus (D_1 > 0); a fully incompressible law is not supported");
  if (!(solver.min_step_mm > 0) || !(solver.initial_step_mm >= solver.min_step_mm) ||
      !(solver.max_step_mm >= solver.initial_step_mm))
    throw FeError("FE model: solver steps must satisfy 0 < min_step <= initial_step <= max_step");
  if (solver.max_newton_iterations < 2) throw FeError("FE model: max_newton_iterations must be at least 2");
  if (!(solver.penalty_factor > 0)) throw FeError("FE model: penalty_factor must be positive");
}

}  // namespace tocd::sim::fe

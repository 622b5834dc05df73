#pragma once

#include <array>
#include <vector>

#include <Eigen/Sparse>

#include "tocd/sim/fe/element.hpp"
#include "tocd/sim/fe/model.hpp"
#include "tocd/sim/fe/result.hpp"

namespace tocd::sim::fe {

/// Rigid pin: hemisphere of radius R with its tip at (0, tip_z), continued by a cylindrical
/// shaft of the same radius above the hemisphere's centre.
struct PinGeometry {
  double radius = 1.5, tip_z = 0;
  /// Signed gap g (> 0: outside the pin), unit normal n pointing from the pin to the point,
  /// and the distance to the centre used for the curvature term (0 on the shaft).
  void query(double r, double z, double& gap, Eigen::Vector2d& n, double& curvature_distance) const;
};

/// A skin top node against the pin (PinGeometry::query at the node's current place).
struct PinContact {
  double gap = 0;                 ///< > 0: outside the pin
  Eigen::Vector2d normal;         ///< from the pin to the node
  double curvature_distance = 0;  ///< to the hemisphere's centre (0 on the shaft)
};

/// One evaluation of the discrete problem at nodal displacements u (all dofs).
struct Evaluation {
  bool valid = false;
  double energy = 0;         ///< internal + contact
  Eigen::VectorXd residual;  ///< free dofs: internal - contact forces
  double residual_norm = 0;
  double internal_force_norm = 0;  ///< over all dofs (reactions included): the force scale
  double pin_force = 0;            ///< sum of contact pressures' z components (per radian / unit depth)
  double max_penetration = 0;
  double contact_radius = 0;
  std::vector<double> contact_force;  ///< per top node (magnitude)
  std::vector<double> top_stiffness;  ///< per top node: largest internal diagonal stiffness of its free dofs
};

/// Global structure: dof numbering, element references, sparse pattern, contact state.
class Assembly {
 public:
  Assembly(const FeModel& model, FeMesh mesh, const tocd::sim::material::HyperelasticLaw& law);

  int dofs() const { return static_cast<int>(eq_.size()); }
  int free_dofs() const { return free_; }
  const FeMesh& mesh() const { return mesh_; }
  const std::vector<int>& top_nodes() const { return top_; }
  const std::vector<ElementReference>& references() const { return refs_; }
  const std::vector<int>& equation() const { return eq_; }
  Eigen::SparseMatrix<double>& stiffness() { return K_; }

  /// Fills ev (and the stiffness when want_stiffness) for displacements u and pin tip z.
  void evaluate(const Eigen::VectorXd& u, double tip_z, bool want_stiffness, Evaluation& ev);

  /// Top node `t` (an index into top_nodes()) against the pin with its tip at tip_z, at
  /// displacements u (all dofs).
  PinContact pin_contact(std::size_t t, const Eigen::VectorXd& u, double tip_z) const;

  std::vector<double> penalty, multiplier;  ///< per top node (augmented Lagrangian)

 private:
  const FeModel& model_;
  FeMesh mesh_;
  const tocd::sim::material::HyperelasticLaw& law_;
  std::vector<int> eq_;  ///< dof -> free equation or -1
  int free_ = 0;
  std::vector<int> top_;
  std::vector<ElementReference> refs_;
  Eigen::SparseMatrix<double> K_;
  std::vector<std::array<int, 64>> slots_;     ///< element (8x8) -> index into K_ values or -1
  std::vector<std::array<int, 4>> top_slots_;  ///< top node 2x2 block -> K_ values or -1
};

}  // namespace tocd::sim::fe

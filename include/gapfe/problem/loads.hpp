#pragma once
// Loads and constraints as the seed's cards give them (Appendix A, Data 5 and 12-15), in the
// library's full-ring convention (types.hpp): a nodal force is the total around the circumference.
#include <array>

#include "gapfe/core/types.hpp"

namespace gapfe {

/// Boundary-condition card (Data 5) for one node. `code` is the bit mask of prescribed
/// displacement components, 1 = u_r, 2 = u_z, 4 = u_theta (codes 0-7 of the seed, docs/theory.md 9);
/// the other components of `value` are nodal forces (total ring force; theta: force, so torque = XT r).
struct NodalCondition {
  int node = 0;
  int code = 0;
  /// (XR, XZ, XT): displacement [length] or total force [force] per component. A std::array, not an
  /// Eigen vector, so that `{n, code}` and `{n, code, {}}` mean zeros rather than uninitialized storage.
  std::array<double, 3> value{};
  /// The components this condition sets (a bit mask as `code`). Where conditions on one node overlap, the
  /// later sets each of its components (DofMap). A deck's card sets all three, as in the seed; a scene's
  /// [[boundary]] only the directions it names, so `fix = ["z"]` on one curve and a force along r on
  /// another leave their shared corner fixed along z and loaded along r.
  int sets = 7;
  bool prescribed(int component) const { return (code >> component) & 1; }
};

/// Uniform traction on the element edge from node M to node N, the element on the left going from
/// M to N (seed Data 13-15). pressure: positive pushes into the body (compression); shear: positive
/// from M to N; transverse_shear: along +theta [stress].
struct EdgeLoad {
  int node_m              = 0;
  int node_n              = 0;
  double pressure         = 0.0;
  double shear            = 0.0;
  double transverse_shear = 0.0;
};

/// Rigid-body motion of the frame (seed Data 12): ACELZ, ANGVEL, ANGACC.
struct InertiaLoad {
  double axial_acceleration   = 0.0;  ///< a_z [length / time^2]; the inertia force is -rho a_z
  double angular_velocity     = 0.0;  ///< omega [rad / time]; centrifugal rho omega^2 r
  double angular_acceleration = 0.0;  ///< omega_dot [rad / time^2]; tangential -rho omega_dot r
};

}  // namespace gapfe

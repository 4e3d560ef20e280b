#pragma once
// Node links: two-node springs on the relative displacement u_b - u_a of a node pair. Every contact
// policy reduces a closed gap pair to one (docs/theory.md 5.2: the seed's "large number" set in N, T, S and
// transformed back is the same as adding a penalty spring k n n^T along the closure direction n), and
// a tangential (friction) spring is one more term of the same 3 x 3 stiffness.
//
// Sign convention: the link pushes node b with  force - stiffness (u_b - u_a)  and node a with the
// opposite, in global (r, z, theta) components; total ring forces like every nodal force (types.hpp).
#include "gapfe/core/types.hpp"

namespace gapfe {

struct NodeLink {
  /// On u_b - u_a [force/length]. Symmetric unless the model's solver reads full storage (a slipping
  /// Coulomb pair's tangent is not; with a symmetric solver the contact driver passes its symmetric part).
  Mat33 stiffness = Mat33::Zero();
  Vec3 force      = Vec3::Zero();  ///< on node b at u_b = u_a [force]

  bool zero() const { return stiffness.isZero(0.0) && force.isZero(0.0); }
  /// Stiffness of the two-node element (a then b, DofsPerNode components each): [K -K; -K K].
  template <int DofsPerNode>
  Mat<2 * DofsPerNode, 2 * DofsPerNode> element_stiffness() const {
    const auto k = stiffness.topLeftCorner<DofsPerNode, DofsPerNode>();
    Mat<2 * DofsPerNode, 2 * DofsPerNode> out;
    out << k, -k, -k, k;
    return out;
  }
  /// Load of the two-node element: -force on a, +force on b.
  template <int DofsPerNode>
  Vec<2 * DofsPerNode> element_load() const {
    Vec<2 * DofsPerNode> out;
    out << -force.head<DofsPerNode>(), force.head<DofsPerNode>();
    return out;
  }
};

}  // namespace gapfe

#pragma once
// What the kinematics needs at one integration point: shape values N (for the hoop term u_r / r),
// their spatial gradients, the radius and the full-ring volume weight 2 pi r |J| w (docs/theory.md 1.2, 1.4).
// Elements produce it (element/point_maps.hpp), kinematics consume it: the one type both contracts
// in core/concepts.hpp name.
#include "gapfe/core/types.hpp"

namespace gapfe {

/// One integration point of an element with NN shape nodes.
/// dN_dx: NN x 2, columns (d/dr, d/dz). weight: 2 pi r |J| w, a volume [length^3].
template <int NN>
struct PointGeometry {
  Vec<NN> N;
  Mat<NN, 2> dN_dx;
  double r      = 0.0;
  double weight = 0.0;
};

}  // namespace gapfe

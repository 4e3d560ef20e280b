#pragma once
// Consistent nodal forces of an edge traction (seed Data 13-15; docs/theory.md 4.2), full ring:
//   F_a = int N_a t 2 pi r ds,   t = -p n + s d (in r, z),   t_theta = q,
// d the unit tangent from M to N, n = (d_z, -d_r) the outward normal (element on the left).
// For a straight 2-node edge and uniform p this gives F_M = 2 pi p L (2 r_M + r_N) / 6: the heavier
// share goes to the node at larger r. 4 Gauss points integrate linear and quadratic edges exactly.
#include "gapfe/core/types.hpp"
#include "gapfe/element/quadrature.hpp"

namespace gapfe {

/// Edge node coordinates x (EN x 2, ordered M, [mid,] N for 3-node edges: M, mid, N) -> forces
/// (EN x 3: r, z, theta components) [force, total ring].
template <int EN>
Mat<EN, 3> edge_forces(const Mat<EN, 2>& x, double pressure, double shear, double transverse_shear) {
  static_assert(EN == 2 || EN == 3);
  using G      = gauss::Line<4>;
  Mat<EN, 3> f = Mat<EN, 3>::Zero();
  for (int q = 0; q < 4; ++q) {
    const double s = G::x[q];
    Vec<EN> n, dn;
    if constexpr (EN == 2) {
      n << 0.5 * (1 - s), 0.5 * (1 + s);
      dn << -0.5, 0.5;
    } else {  // ordered (M, mid, N) at s = -1, 0, 1
      n << 0.5 * s * (s - 1), 1 - s * s, 0.5 * s * (s + 1);
      dn << s - 0.5, -2 * s, s + 0.5;
    }
    const Vec2 pos = x.transpose() * n, tangent = x.transpose() * dn;
    const double jac = tangent.norm();
    const Vec2 d     = tangent / jac, outward(d(1), -d(0));
    const Vec2 t     = -pressure * outward + shear * d;
    const double w   = kTwoPi * pos(0) * jac * G::w[q];
    for (int a = 0; a < EN; ++a) {
      f(a, 0) += n(a) * t(0) * w;
      f(a, 1) += n(a) * t(1) * w;
      f(a, 2) += n(a) * transverse_shear * w;
    }
  }
  return f;
}

}  // namespace gapfe

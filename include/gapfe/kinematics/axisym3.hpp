#pragma once
// Axisym3 (SAGA): 3 DOF per node (u_r, u_z, u_theta); all six strains (docs/theory.md 1.1-1.2):
//   z-theta = u_theta,z,  theta-r = u_theta,r - u_theta / r.
// B for node a (columns u_r, u_z, u_theta), rows [rr, zz, hoop, rz, z-theta, theta-r]:
//   [ N_a,r    0      0             ]
//   [ 0        N_a,z  0             ]
//   [ N_a / r  0      0             ]
//   [ N_a,z    N_a,r  0             ]
//   [ 0        0      N_a,z         ]
//   [ 0        0      N_a,r - N_a/r ]
// The in-plane and torsional groups couple only through the material matrix.
#include "gapfe/core/point_geometry.hpp"

namespace gapfe {

struct Axisym3 {
  static constexpr int kDofsPerNode          = 3;
  static constexpr int kStrain               = 6;
  static constexpr std::array<int, 6> kVoigt = {0, 1, 2, 3, 4, 5};

  template <int NN>
  static Mat<6, 3 * NN> B(const PointGeometry<NN>& g) {
    Mat<6, 3 * NN> b = Mat<6, 3 * NN>::Zero();
    for (int a = 0; a < NN; ++a) {
      const double hoop = g.N(a) / g.r;
      b(0, 3 * a)       = g.dN_dx(a, 0);
      b(1, 3 * a + 1)   = g.dN_dx(a, 1);
      b(2, 3 * a)       = hoop;
      b(3, 3 * a)       = g.dN_dx(a, 1);
      b(3, 3 * a + 1)   = g.dN_dx(a, 0);
      b(4, 3 * a + 2)   = g.dN_dx(a, 1);
      b(5, 3 * a + 2)   = g.dN_dx(a, 0) - hoop;
    }
    return b;
  }
};

}  // namespace gapfe

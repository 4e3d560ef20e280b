#pragma once
// Axisym2 (SAAS): 2 DOF per node (u_r, u_z); strains [rr, zz, hoop, rz] = global Voigt slots 0..3
// (docs/theory.md 1.1-1.2). B for node a (columns u_r, u_z):
//   [ N_a,r    0    ]
//   [ 0        N_a,z]
//   [ N_a / r  0    ]   hoop; r > 0 at every integration point (Gauss points are interior)
//   [ N_a,z    N_a,r]
// With this kinematics the z-theta and theta-r strains are held at zero: the 6x6 material matrix
// reduces to its 4x4 block exactly (their stresses are reactions that do no work). That matches the
// physics only when the material couples nothing into them (isotropic, or ALPHA = 0).
#include "gapfe/core/point_geometry.hpp"

namespace gapfe {

struct Axisym2 {
  static constexpr int kDofsPerNode          = 2;
  static constexpr int kStrain               = 4;
  static constexpr std::array<int, 4> kVoigt = {0, 1, 2, 3};  // rows within the global Voigt-6 vector

  template <int NN>
  static Mat<4, 2 * NN> B(const PointGeometry<NN>& g) {
    Mat<4, 2 * NN> b = Mat<4, 2 * NN>::Zero();
    for (int a = 0; a < NN; ++a) {
      b(0, 2 * a)     = g.dN_dx(a, 0);
      b(1, 2 * a + 1) = g.dN_dx(a, 1);
      b(2, 2 * a)     = g.N(a) / g.r;
      b(3, 2 * a)     = g.dN_dx(a, 1);
      b(3, 2 * a + 1) = g.dN_dx(a, 0);
    }
    return b;
  }
};

}  // namespace gapfe

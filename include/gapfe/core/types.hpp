#pragma once
// Vocabulary types and the conventions every other header relies on (docs/theory.md section 0).
//
// Coordinates: (r, z, theta), r >= 0; everything is a function of (r, z) only.
// Units: any consistent set; the library never converts (SI in the examples). Angles are radians
//   internally (the deck reader converts the cards' degrees).
// Voigt order (global): [rr, zz, tt (hoop), rz, z-theta, theta-r], engineering shear strains,
//   tensor shear stresses. Material axes use the same pair pattern in (N, S, T) order:
//   [NN, SS, TT, NS, ST, TN], the order of the E and G cards (seed Data 10b).
// Integration: full ring, dV = 2 pi r dr dz. Every nodal force, reaction and stiffness is a total
//   over 360 degrees (as in Abaqus and ANSYS). A per-radian legacy load is 1/(2 pi) of ours.
// Sign: tension positive; a pressure is positive in compression (seed Data 13).
// DOF order per node: (u_r, u_z, u_theta); the 2-DOF (SAAS) kinematics drops u_theta.
#include <array>
#include <cmath>
#include <numbers>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace gapfe {

template <int N>
using Vec = Eigen::Matrix<double, N, 1>;
template <int R, int C>
using Mat   = Eigen::Matrix<double, R, C>;
using Vec2  = Vec<2>;
using Vec3  = Vec<3>;
using Vec6  = Vec<6>;
using Mat33 = Mat<3, 3>;
using Mat66 = Mat<6, 6>;
using VecX  = Eigen::VectorXd;
using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Global Voigt slots (see the header comment).
namespace voigt {
inline constexpr int rr = 0, zz = 1, hoop = 2, rz = 3, z_theta = 4, theta_r = 5;
/// Tensor index pairs (i, j) of each Voigt slot; the same table serves (r, z, theta) and (N, S, T).
inline constexpr std::array<std::array<int, 2>, 6> kPairs{{{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {2, 0}}};
/// The symmetric 3 x 3 tensor of a stress in Voigt form (tensor shear components), axes (r, z, theta).
inline Mat<3, 3> stress_tensor(const Vec<6>& s) {
  Mat<3, 3> t;
  for (int k = 0; k < 6; ++k) t(kPairs[k][0], kPairs[k][1]) = t(kPairs[k][1], kPairs[k][0]) = s(k);
  return t;
}
/// The von Mises equivalent stress sqrt(3 J2) of a stress in Voigt form (the same invariant in any axes).
inline double von_mises(const Vec<6>& s) {
  const double normal = (s(rr) - s(zz)) * (s(rr) - s(zz)) + (s(zz) - s(hoop)) * (s(zz) - s(hoop)) +
                        (s(hoop) - s(rr)) * (s(hoop) - s(rr));
  const double shear = s(rz) * s(rz) + s(z_theta) * s(z_theta) + s(theta_r) * s(theta_r);
  return std::sqrt(0.5 * normal + 3 * shear);
}
}  // namespace voigt

/// Nodal displacement components.
namespace dof {
inline constexpr int r = 0, z = 1, theta = 2;
/// Component names for messages, indexed by component.
inline constexpr std::array<const char*, 3> kName{"u_r", "u_z", "u_theta"};
}  // namespace dof

}  // namespace gapfe

#pragma once
// The two ways an element fills a PointGeometry (core/point_geometry.hpp): the isoparametric map and
// the constant-strain triangle.
#include "gapfe/core/point_geometry.hpp"

namespace gapfe {

/// Isoparametric map at one reference point. x: NN x 2 nodal (r, z); dN_dxi: NN x 2 (d/dxi, d/deta).
/// Returns det J through `det`; a non-positive det means an inverted or degenerate element, which
/// mesh validation reports before any kernel runs.
template <int NN>
inline PointGeometry<NN> isoparametric_point(const Mat<NN, 2>& x, const Vec<NN>& N, const Mat<NN, 2>& dN_dxi,
                                             double rule_weight, double& det) {
  // J = [[r_xi, z_xi], [r_eta, z_eta]]; [N_xi; N_eta] = J [N_r; N_z].
  const Mat<2, 2> J = dN_dxi.transpose() * x;
  det               = J(0, 0) * J(1, 1) - J(0, 1) * J(1, 0);
  Mat<2, 2> J_inv_t;  // (J^-1)^T
  J_inv_t << J(1, 1), -J(1, 0), -J(0, 1), J(0, 0);
  J_inv_t /= det;
  PointGeometry<NN> g;
  g.N      = N;
  g.dN_dx  = dN_dxi * J_inv_t;
  g.r      = N.dot(x.col(0));
  g.weight = kTwoPi * g.r * det * rule_weight;
  return g;
}

/// Linear (constant-strain) triangle on nodes `tri` of an NN-node shape set, evaluated at area
/// coordinates (L2, L3) with reference weight w (the reference triangle has area 1/2). The
/// gradients are constant: dN_i/dr = b_i / 2A, dN_i/dz = c_i / 2A with b_i = z_j - z_k,
/// c_i = r_k - r_j, (i, j, k) cyclic (docs/theory.md 2 item 2).
template <int NN>
inline PointGeometry<NN> cst_point(const Mat<NN, 2>& x, const std::array<int, 3>& tri, double L2, double L3,
                                   double rule_weight, double& two_area) {
  const double r1 = x(tri[0], 0), z1 = x(tri[0], 1);
  const double r2 = x(tri[1], 0), z2 = x(tri[1], 1);
  const double r3 = x(tri[2], 0), z3 = x(tri[2], 1);
  two_area = (r2 - r1) * (z3 - z1) - (r3 - r1) * (z2 - z1);
  PointGeometry<NN> g;
  g.N.setZero();
  g.dN_dx.setZero();
  g.N(tri[0])        = 1.0 - L2 - L3;
  g.N(tri[1])        = L2;
  g.N(tri[2])        = L3;
  g.dN_dx(tri[0], 0) = (z2 - z3) / two_area;
  g.dN_dx(tri[1], 0) = (z3 - z1) / two_area;
  g.dN_dx(tri[2], 0) = (z1 - z2) / two_area;
  g.dN_dx(tri[0], 1) = (r3 - r2) / two_area;
  g.dN_dx(tri[1], 1) = (r1 - r3) / two_area;
  g.dN_dx(tri[2], 1) = (r2 - r1) / two_area;
  g.r                = g.N(tri[0]) * r1 + L2 * r2 + L3 * r3;
  g.weight           = kTwoPi * g.r * two_area * rule_weight;  // |J| = 2A on the reference triangle
  return g;
}

}  // namespace gapfe

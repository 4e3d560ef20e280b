#pragma once
// Bilinear fields on Quad4's square: their coefficients from corner or Gauss-point values, and the stresses
// of a linear law at a plain Quad4's 2 x 2 points with 2 DOF per node (Quad4Stresses), for the error
// estimate's pass over every cell of every increment (post/error_estimate.hpp). The same mathematics as
// ElementKernel<Axisym2, Quad4>::strain (docs/theory.md 1.2; element/isoparametric.hpp), written through
// the bilinear fields' coefficients instead of B: r, z, u_r and u_z are each c0 + c1 xi + c2 eta + c3 xi eta
// in the cell, so at a point
//   J = [[r_xi, z_xi], [r_eta, z_eta]],  r_xi = c1 + c3 eta,  r_eta = c2 + c3 xi  (and so z, u_r, u_z),
//   [f_r; f_z] = J^-1 [f_xi; f_eta] = [z_eta f_xi - z_xi f_eta; r_xi f_eta - r_eta f_xi] / det J,
//   strain [rr, zz, hoop, rz] = [u_r,r; u_z,z; u_r / r; u_r,z + u_z,r].
// About a fifth of the generic path's instructions (no shape-function arrays, no B, no 6 x 6 stress); the
// generic path is the reference (tests/test_estimate.cpp holds the two to round-off).
#include <array>

#include "gapfe/core/types.hpp"
#include "gapfe/element/quad4.hpp"
#include "gapfe/element/quadrature.hpp"

namespace gapfe::detail {

static_assert(Quad4::kCorners[0][0] == -1 && Quad4::kCorners[0][1] == -1 && Quad4::kCorners[1][0] == 1 &&
                  Quad4::kCorners[1][1] == -1 && Quad4::kCorners[2][0] == 1 && Quad4::kCorners[2][1] == 1 &&
                  Quad4::kCorners[3][0] == -1 && Quad4::kCorners[3][1] == 1,
              "bilinear(): the corners counterclockwise from (-1, -1)");
static_assert(Quad4::kRule.point[0][0] < 0 && Quad4::kRule.point[0][1] < 0 && Quad4::kRule.point[1][0] > 0 &&
                  Quad4::kRule.point[1][1] < 0 && Quad4::kRule.point[2][0] < 0 &&
                  Quad4::kRule.point[2][1] > 0 && Quad4::kRule.point[3][0] > 0 &&
                  Quad4::kRule.point[3][1] > 0,
              "through_points(): the 2 x 2 points with xi fastest");
static_assert(Quad4::kRule.point[3][0] == gauss::Line<2>::a && Quad4::kRule.point[3][1] == gauss::Line<2>::a,
              "through_points(): the points at +-1/sqrt 3");

/// The coefficients (c0, c1, c2, c3) of c0 + c1 xi + c2 eta + c3 xi eta through the values at the corners
/// (-1, -1), (1, -1), (1, 1), (-1, 1): Quad4's shape functions (1 + xi_c xi)(1 + eta_c eta) / 4 written out.
template <class T>
std::array<T, 4> bilinear(const T& v0, const T& v1, const T& v2, const T& v3) {
  return {(v0 + v1 + v2 + v3) / 4, (v1 + v2 - v0 - v3) / 4, (v2 + v3 - v0 - v1) / 4, (v0 + v2 - v1 - v3) / 4};
}

/// The same through the values at Quad4's 2 x 2 Gauss points (+-a, +-a), a = 1/sqrt 3, xi fastest: the
/// Lagrange field that the stresses kept there define (post/cell_error.hpp).
template <class T>
std::array<T, 4> through_points(const T* at) {
  constexpr double a = gauss::Line<2>::a;
  std::array<T, 4> c = bilinear<T>(at[0], at[1], at[3], at[2]);
  c[1] /= a, c[2] /= a, c[3] /= a * a;
  return c;
}

/// Stress = stiffness * strain - thermal at each of a Quad4's 2 x 2 points (Quad4::kRule's order), with its
/// position (r, z) and volume weight 2 pi r det J w; `ue` the corners' (u_r, u_z).
struct Quad4Stresses {
  std::array<Vec<4>, 4> stress;
  std::array<Vec2, 4> position;
  std::array<double, 4> weight;

  Quad4Stresses(const Mat<4, 2>& x, const Vec<8>& ue, const Mat<4, 4>& stiffness, const Vec<4>& thermal) {
    const auto r  = bilinear(x(0, 0), x(1, 0), x(2, 0), x(3, 0)),
               z  = bilinear(x(0, 1), x(1, 1), x(2, 1), x(3, 1));
    const auto ur = bilinear(ue(0), ue(2), ue(4), ue(6)), uz = bilinear(ue(1), ue(3), ue(5), ue(7));
    for (int q = 0; q < 4; ++q) {
      const double xi = Quad4::kRule.point[q][0], eta = Quad4::kRule.point[q][1];
      const double r_xi = r[1] + r[3] * eta, r_eta = r[2] + r[3] * xi;
      const double z_xi = z[1] + z[3] * eta, z_eta = z[2] + z[3] * xi;
      const double det = r_xi * z_eta - z_xi * r_eta, inv = 1.0 / det;
      const double ur_xi = ur[1] + ur[3] * eta, ur_eta = ur[2] + ur[3] * xi;
      const double uz_xi = uz[1] + uz[3] * eta, uz_eta = uz[2] + uz[3] * xi;
      const double at_r = r[0] + r[1] * xi + r[2] * eta + r[3] * xi * eta;
      const double u_r  = ur[0] + ur[1] * xi + ur[2] * eta + ur[3] * xi * eta;
      const Vec<4> strain((z_eta * ur_xi - z_xi * ur_eta) * inv, (r_xi * uz_eta - r_eta * uz_xi) * inv,
                          u_r / at_r,
                          ((r_xi * ur_eta - r_eta * ur_xi) + (z_eta * uz_xi - z_xi * uz_eta)) * inv);
      stress[q].noalias() = stiffness * strain;
      stress[q] -= thermal;
      position[q] = Vec2(at_r, z[0] + z[1] * xi + z[2] * eta + z[3] * xi * eta);
      weight[q]   = kTwoPi * at_r * det * Quad4::kRule.weight[q];
    }
  }
};

}  // namespace gapfe::detail

#pragma once
// Quad4Axisym2Batch: the Quad4 2-DOF stiffness of W elements at once, in structure-of-arrays form, so
// the compiler vectorizes across elements. Same mathematics as ElementKernel<Axisym2, Quad4>
// (docs/theory.md 1.2, 2x2 Gauss, full ring), but B is never formed: its zero structure is written out.
//
// DATA LAYOUT ASSUMPTIONS (lane l = element within the batch, fastest index):
//   r[a][l], z[a][l]        nodal coordinates, a = 0..3 counterclockwise
//   d[q][m][l]              material matrix at Gauss point q, the 10 entries of the symmetric 4x4 block
//                           [rr, zz, hoop, rz] in order (0,0) (0,1) (0,2) (0,3) (1,1) (1,2) (1,3) (2,2) (2,3)
//                           (3,3); per point so that a plastic tangent fits (set all four alike for
//                           elasticity)
//   k[c][l]                 the 8x8 stiffness, upper triangle i <= j row-major (36 entries), DOFs
//                           (u_r0, u_z0, u_r1, u_z1, ...): the order scatter_offsets() uses
// Cost: about 2.2 kflop per element (see BENCHMARKS.md).
#include <array>

#include "gapfe/core/types.hpp"
#include "gapfe/element/quad4.hpp"

namespace gapfe {

template <int W = 8>
struct Quad4Axisym2Batch {
  static constexpr int kLanes = W;
  alignas(64) double r[4][W];
  alignas(64) double z[4][W];
  alignas(64) double d[4][10][W];
  alignas(64) double k[36][W];

  /// Broadcast one 4x4 (symmetric) material block to every point of lane l.
  template <class Derived>
  void set_material(int l, const Eigen::MatrixBase<Derived>& D) {
    static constexpr std::array<std::array<int, 2>, 10> kIdx{
        {{0, 0}, {0, 1}, {0, 2}, {0, 3}, {1, 1}, {1, 2}, {1, 3}, {2, 2}, {2, 3}, {3, 3}}};
    for (int q = 0; q < 4; ++q)
      for (int m = 0; m < 10; ++m) d[q][m][l] = D(kIdx[m][0], kIdx[m][1]);
  }

  void compute() {
    for (int c = 0; c < 36; ++c)
      for (int l = 0; l < W; ++l) k[c][l] = 0.0;
    for (int q = 0; q < 4; ++q) point(q);
  }

 private:
  void point(int q) {
    const double xi = Quad4::kRule.point[q][0], eta = Quad4::kRule.point[q][1];
    const double wq    = kTwoPi * Quad4::kRule.weight[q];
    const Vec<4> n     = Quad4::N(xi, eta);  // the element's own shape functions, evaluated once per point
    const Mat<4, 2> dn = Quad4::dN(xi, eta);
    const double dxi[4]{dn(0, 0), dn(1, 0), dn(2, 0), dn(3, 0)},
        deta[4]{dn(0, 1), dn(1, 1), dn(2, 1), dn(3, 1)};
    alignas(64) double nr[4][W], nz[4][W], hoop[4][W], w[W];
    for (int l = 0; l < W; ++l) {
      double r_xi = 0, z_xi = 0, r_eta = 0, z_eta = 0, rq = 0;
      for (int a = 0; a < 4; ++a) {
        r_xi += dxi[a] * r[a][l], z_xi += dxi[a] * z[a][l];
        r_eta += deta[a] * r[a][l], z_eta += deta[a] * z[a][l];
        rq += n(a) * r[a][l];
      }
      const double det = r_xi * z_eta - z_xi * r_eta, inv = 1.0 / det, inv_r = 1.0 / rq;
      // [N_r; N_z] = J^-1 [N_xi; N_eta], J = [[r_xi, z_xi], [r_eta, z_eta]]
      for (int a = 0; a < 4; ++a) {
        nr[a][l]   = (z_eta * dxi[a] - z_xi * deta[a]) * inv;
        nz[a][l]   = (r_xi * deta[a] - r_eta * dxi[a]) * inv;
        hoop[a][l] = n(a) * inv_r;
      }
      w[l] = wq * rq * det;
    }
    const auto& dq = d[q];
    // DB (4 strains x 8 DOFs), scaled by the weight: column 2a = D (N_r, 0, hoop, N_z)^T,
    // column 2a + 1 = D (0, N_z, 0, N_r)^T.
    alignas(64) double db[4][8][W];
    for (int a = 0; a < 4; ++a)
      for (int l = 0; l < W; ++l) {
        const double x = nr[a][l] * w[l], y = nz[a][l] * w[l], h = hoop[a][l] * w[l];
        const double d00 = dq[0][l], d01 = dq[1][l], d02 = dq[2][l], d03 = dq[3][l], d11 = dq[4][l];
        const double d12 = dq[5][l], d13 = dq[6][l], d22 = dq[7][l], d23 = dq[8][l], d33 = dq[9][l];
        db[0][2 * a][l]     = d00 * x + d02 * h + d03 * y;
        db[1][2 * a][l]     = d01 * x + d12 * h + d13 * y;
        db[2][2 * a][l]     = d02 * x + d22 * h + d23 * y;
        db[3][2 * a][l]     = d03 * x + d23 * h + d33 * y;
        db[0][2 * a + 1][l] = d01 * y + d03 * x;
        db[1][2 * a + 1][l] = d11 * y + d13 * x;
        db[2][2 * a + 1][l] = d12 * y + d23 * x;
        db[3][2 * a + 1][l] = d13 * y + d33 * x;
      }
    // K(i, j) += B(:, i) . DB(:, j), i <= j; B(:, 2a) = (N_r, 0, hoop, N_z), B(:, 2a + 1) = (0, N_z, 0, N_r).
    int c = 0;
    for (int i = 0; i < 8; ++i) {
      const int a = i / 2;
      for (int j = i; j < 8; ++j, ++c)
        for (int l = 0; l < W; ++l) {
          if (i % 2 == 0)
            k[c][l] += nr[a][l] * db[0][j][l] + hoop[a][l] * db[2][j][l] + nz[a][l] * db[3][j][l];
          else
            k[c][l] += nz[a][l] * db[1][j][l] + nr[a][l] * db[3][j][l];
        }
    }
  }
};

}  // namespace gapfe

#pragma once
// A cell's share of the recovery error estimate (post/error_estimate.hpp): the integrals over the cell of
//   eta_e^2   = integral of (sigma* - sigma_h)^T C^-1 (sigma* - sigma_h) dV   and
//   |u_h|_e^2 = integral of sigma_h^T C^-1 sigma_h dV,
// sigma* interpolated from the cell's nodes, sigma_h through its stiffness points' values, C the law's
// elastic stiffness, dV = 2 pi r dA. Exact on quad4 and the constant-strain triangles; Quad8 on 4 x 4 Gauss
// points, Tri6 on its own points (docs/accuracy.md).
#include <array>

#include "gapfe/core/types.hpp"
#include "gapfe/element/quadrature.hpp"

namespace gapfe {

namespace detail {

/// eta_e^2 and |u_h|_e^2 of a bilinear quadrilateral (Quad4 and its B-bar form) from sigma* at its corners
/// and sigma_h at its 2 x 2 Gauss points, `at`. Both fields are bilinear in (xi, eta), c0 + c1 xi + c2 eta +
/// c3 xi eta: sigma* through the corners, sigma_h through the Gauss points' values (what a law with history
/// keeps; a linear law's own field but for the hoop strain's 1 / r). Their squares weighed by C^-1 and by
/// 2 pi r det J are then sums of the coefficients' products c_k^T C^-1 c_l times the moments of
/// (1, xi, eta, xi eta) under the weight. The weight is a polynomial too (r bilinear, det J linear on a
/// bilinear map), so the moments are sums of the square's integrals of xi^a eta^b, 2 / (a + 1) times
/// 2 / (b + 1) for a, b even and 0 otherwise: what 3 x 3 Gauss points give, without the points. Returns
/// {eta_e^2, |u_h|_e^2}.
template <class E, int S>
std::array<double, 2> bilinear_cell_energies(const Mat<4, 2>& x, const std::array<Vec<S>, 4>& corner,
                                             const Vec<S>* at, const Mat<S, S>& compliance) {
  // The map's coefficients in (1, xi, eta, xi eta): N_c = (1 + xi_c xi)(1 + eta_c eta) / 4.
  Mat<4, 2> map = Mat<4, 2>::Zero();
  std::array<Vec<S>, 4> diff, held;  // the coefficients of sigma* - sigma_h and of sigma_h
  for (int k = 0; k < 4; ++k) diff[k].setZero(), held[k].setZero();
  for (int c = 0; c < 4; ++c) {
    const double a = E::kCorners[c][0], b = E::kCorners[c][1];
    map.row(0) += x.row(c) / 4, map.row(1) += a * x.row(c) / 4, map.row(2) += b * x.row(c) / 4;
    map.row(3) += a * b * x.row(c) / 4;
    diff[0] += corner[c] / 4, diff[1] += a * corner[c] / 4, diff[2] += b * corner[c] / 4;
    diff[3] += a * b * corner[c] / 4;
  }
  // sigma_h: Lagrange through (+-1/sqrt 3, +-1/sqrt 3), (1 + 3 xi_q xi)(1 + 3 eta_q eta) / 4.
  for (int q = 0; q < 4; ++q) {
    const double a = 3 * E::kRule.point[q][0], b = 3 * E::kRule.point[q][1];
    held[0] += at[q] / 4, held[1] += a * at[q] / 4, held[2] += b * at[q] / 4, held[3] += a * b * at[q] / 4;
  }
  for (int k = 0; k < 4; ++k) diff[k] -= held[k];
  // det J = j0 + j1 xi + j2 eta (the xi eta terms cancel); the weight 2 pi r det J as w[a][b] xi^a eta^b.
  const Vec<4> r = map.col(0), z = map.col(1);
  const double j0 = r(1) * z(2) - z(1) * r(2), j1 = r(1) * z(3) - z(1) * r(3), j2 = r(3) * z(2) - z(3) * r(2);
  double w[3][3]                   = {{r(0) * j0, r(0) * j2 + r(2) * j0, r(2) * j2},
                                      {r(0) * j1 + r(1) * j0, r(1) * j2 + r(2) * j1 + r(3) * j0, r(3) * j2},
                                      {r(1) * j1, r(3) * j1, 0}};
  static constexpr double line[5]  = {2, 0, 2.0 / 3, 0, 2.0 / 5};       // integral of t^p over [-1, 1]
  static constexpr int power[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};  // of (1, xi, eta, xi eta)
  std::array<double, 2> out{0, 0};
  for (int k = 0; k < 4; ++k) {
    const Vec<S> cd = compliance * diff[k], ch = compliance * held[k];
    for (int l = k; l < 4; ++l) {
      double moment = 0;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          moment += w[a][b] * line[a + power[k][0] + power[l][0]] * line[b + power[k][1] + power[l][1]];
      moment *= k == l ? kTwoPi : 2 * kTwoPi;  // the (l, k) term with the (k, l) one
      out[0] += moment * diff[l].dot(cd), out[1] += moment * held[l].dot(ch);
    }
  }
  return out;
}

/// eta_e^2 and |u_h|_e^2 of an 8-node quadrilateral from sigma* at its nodes and sigma_h at its 3 x 3 Gauss
/// points, `at`, on 4 x 4 Gauss points: sigma* through the nodes (its shape functions), sigma_h biquadratic
/// through the 3 x 3 points' values (Lagrange through -a, 0, a, a = sqrt(3/5), in each direction).
template <class E, int S>
std::array<double, 2> quadratic_cell_energies(const Mat<8, 2>& x, const std::array<Vec<S>, 8>& node,
                                              const Vec<S>* at, const Mat<S, S>& compliance) {
  constexpr auto rule = gauss::square<4>();
  constexpr double a  = gauss::Line<3>::a;
  const auto lagrange = [&](double t) {
    return Vec<3>(t * (t - a) / (2 * a * a), (a * a - t * t) / (a * a), t * (t + a) / (2 * a * a));
  };
  std::array<double, 2> out{0, 0};
  double det = 0;
  for (int q = 0; q < 16; ++q) {
    const double xi = rule.point[q][0], eta = rule.point[q][1];
    const auto g    = E::at(x, xi, eta, rule.weight[q], det);
    const Vec<3> li = lagrange(xi), lj = lagrange(eta);
    Vec<S> held = Vec<S>::Zero(), diff = Vec<S>::Zero();
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) held += li(i) * lj(j) * at[3 * j + i];  // square<3>: xi fastest
    for (int c = 0; c < 8; ++c) diff += g.N(c) * node[c];
    diff -= held;
    out[0] += g.weight * diff.dot(compliance * diff), out[1] += g.weight * held.dot(compliance * held);
  }
  return out;
}

/// eta_e^2 and |u_h|_e^2 of a 6-node triangle on its own stiffness points: sigma* through the nodes (its
/// shape functions) against sigma_h where it was computed. The degree-4 rule integrates the quadratic sigma*
/// against the linear part of sigma_h exactly but for the weight r; the estimate needs no more.
template <class E, int S>
std::array<double, 2> triangle_cell_energies(const Mat<6, 2>& x, const std::array<Vec<S>, 6>& node,
                                             const Vec<S>* at, const Mat<S, S>& compliance) {
  std::array<double, 2> out{0, 0};
  double det = 0;
  for (int q = 0; q < E::kStiffnessPoints; ++q) {
    const auto g = E::stiffness_point(x, q, det);
    Vec<S> diff  = -at[q];
    for (int c = 0; c < 6; ++c) diff += g.N(c) * node[c];
    out[0] += g.weight * diff.dot(compliance * diff), out[1] += g.weight * at[q].dot(compliance * at[q]);
  }
  return out;
}

/// The constant-strain triangles of a cell, as shape-node indices: the legacy quadrilateral's four, a
/// triangle itself. Stiffness point q is triangle q's centroid.
template <class E>
constexpr auto cst_triangles() {
  if constexpr (requires { E::kTriangles; })
    return E::kTriangles;
  else
    return std::array<std::array<int, 3>, 1>{E::kTri};
}

/// integral over a straight triangle of d^T K d 2 pi r dA, d linear (d_a at its corners), exactly:
/// sum over a, b, c of (d_a^T K d_b) r_c times the integral of L_a L_b L_c, which is A / 10, A / 30 or
/// A / 60 as a, b, c are all equal, two equal or all different (the integral of L1^i L2^j L3^k is
/// 2 A i! j! k! / (i + j + k + 2)!).
template <int S>
double linear_field_energy(const std::array<Vec<S>, 3>& d, const Mat<S, S>& compliance, const Vec<3>& r,
                           double area) {
  const double all = r.sum();
  const std::array<Vec<S>, 3> cd{compliance * d[0], compliance * d[1], compliance * d[2]};
  double sum = 0;
  for (int a = 0; a < 3; ++a) {
    sum += d[a].dot(cd[a]) * (r(a) / 10 + (all - r(a)) / 30);
    for (int b = a + 1; b < 3; ++b)  // (a, b) and (b, a)
      sum += 2 * d[a].dot(cd[b]) * ((r(a) + r(b)) / 30 + (all - r(a) - r(b)) / 60);
  }
  return kTwoPi * area * sum;
}

}  // namespace detail

}  // namespace gapfe

#pragma once
// A cell's share of the recovery error estimate (post/error_estimate.hpp): the integral over the cell of
//   eta_e^2 = integral of (sigma* - sigma_h)^T C^-1 (sigma* - sigma_h) dV,
// sigma* interpolated from the cell's nodes, sigma_h through its stiffness points' values, C the law's
// elastic stiffness, dV = 2 pi r dA. Exact on quad4 and the constant-strain triangles; Quad8 on 4 x 4 Gauss
// points, Tri6 on its own points (docs/accuracy.md). The solution's own norm |u_h|^2 is a sum over the
// stiffness points, taken where their stresses are (error_estimate.hpp).
#include <array>

#include "gapfe/core/types.hpp"
#include "gapfe/element/quadrature.hpp"
#include "gapfe/post/bilinear_fields.hpp"

namespace gapfe {

namespace detail {

/// eta_e^2 of a bilinear quadrilateral (Quad4 and its B-bar form) from sigma* at its corners and sigma_h at
/// its 2 x 2 Gauss points, `at`. Both fields are bilinear in (xi, eta), c0 + c1 xi + c2 eta + c3 xi eta:
/// sigma* through the corners, sigma_h through the Gauss points' values (what a law with history keeps; a
/// linear law's own field but for the hoop strain's 1 / r). The square of their difference weighed by C^-1
/// and by 2 pi r det J is then a sum of its coefficients' products c_k^T C^-1 c_l times the moments of (1,
/// xi, eta, xi eta) under the weight. The weight is a polynomial too (r bilinear, det J linear on a bilinear
/// map), so the moments are sums of the square's integrals of xi^a eta^b, 2 / (a + 1) times 2 / (b + 1) for
/// a, b even and 0 otherwise: what 3 x 3 Gauss points give, without the points.
template <int S>
double bilinear_cell_error(const Mat<4, 2>& x, const std::array<Vec<S>, 4>& corner, const Vec<S>* at,
                           const Mat<S, S>& compliance) {
  // The coefficients of (1, xi, eta, xi eta): of the map, and of sigma* - sigma_h.
  const auto r    = bilinear(x(0, 0), x(1, 0), x(2, 0), x(3, 0)),
             z    = bilinear(x(0, 1), x(1, 1), x(2, 1), x(3, 1));
  const auto star = bilinear(corner[0], corner[1], corner[2], corner[3]), held = through_points(at);
  std::array<Vec<S>, 4> diff;
  for (int k = 0; k < 4; ++k) diff[k] = star[k] - held[k];
  // det J = j0 + j1 xi + j2 eta (the xi eta terms cancel); the weight r det J as w_ab xi^a eta^b.
  const double j0 = r[1] * z[2] - z[1] * r[2], j1 = r[1] * z[3] - z[1] * r[3], j2 = r[3] * z[2] - z[3] * r[2];
  const double w00 = r[0] * j0, w01 = r[0] * j2 + r[2] * j0, w02 = r[2] * j2, w10 = r[0] * j1 + r[1] * j0,
               w11 = r[1] * j2 + r[2] * j1 + r[3] * j0, w12 = r[3] * j2, w20 = r[1] * j1, w21 = r[3] * j1;
  // The moments m_kl = integral of b_k b_l w over the square, b = (1, xi, eta, xi eta): the integral of
  // xi^a eta^b is 2 / (a + 1) times 2 / (b + 1) for a and b even, 0 otherwise (so 4, 4/3, 4/9, 4/5, 4/15);
  // off the diagonal doubled, for the (l, k) term with the (k, l) one.
  constexpr double c1 = 4.0, c3 = 4.0 / 3, c9 = 4.0 / 9, c5 = 4.0 / 5, c15 = 4.0 / 15;
  const double m[4][4] = {
      {c1 * w00 + c3 * (w02 + w20), 2 * (c3 * w10 + c9 * w12), 2 * (c3 * w01 + c9 * w21), 2 * c9 * w11},
      {0, c3 * w00 + c9 * w02 + c5 * w20, 2 * c9 * w11, 2 * (c9 * w01 + c15 * w21)},
      {0, 0, c3 * w00 + c5 * w02 + c9 * w20, 2 * (c9 * w10 + c15 * w12)},
      {0, 0, 0, c9 * w00 + c15 * (w02 + w20)}};
  // sum over k <= l of m_kl c_k^T C^-1 c_l = sum over k of c_k^T C^-1 (sum over l >= k of m_kl c_l).
  double error = 0;
  for (int k = 0; k < 4; ++k) {
    Vec<S> sum = m[k][k] * diff[k];
    for (int l = k + 1; l < 4; ++l) sum += m[k][l] * diff[l];
    error += diff[k].dot(compliance * sum);
  }
  return kTwoPi * error;
}

/// eta_e^2 of an 8-node quadrilateral from sigma* at its nodes and sigma_h at its 3 x 3 Gauss
/// points, `at`, on 4 x 4 Gauss points: sigma* through the nodes (its shape functions), sigma_h biquadratic
/// through the 3 x 3 points' values (Lagrange through -a, 0, a, a = sqrt(3/5), in each direction).
template <class E, int S>
double quadratic_cell_error(const Mat<8, 2>& x, const std::array<Vec<S>, 8>& node, const Vec<S>* at,
                            const Mat<S, S>& compliance) {
  constexpr auto rule = gauss::square<4>();
  constexpr double a  = gauss::Line<3>::a;
  const auto lagrange = [&](double t) {
    return Vec<3>(t * (t - a) / (2 * a * a), (a * a - t * t) / (a * a), t * (t + a) / (2 * a * a));
  };
  double error = 0, det = 0;
  for (int q = 0; q < 16; ++q) {
    const double xi = rule.point[q][0], eta = rule.point[q][1];
    const auto g    = E::at(x, xi, eta, rule.weight[q], det);
    const Vec<3> li = lagrange(xi), lj = lagrange(eta);
    Vec<S> held = Vec<S>::Zero(), diff = Vec<S>::Zero();
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) held += li(i) * lj(j) * at[3 * j + i];  // square<3>: xi fastest
    for (int c = 0; c < 8; ++c) diff += g.N(c) * node[c];
    diff -= held;
    error += g.weight * diff.dot(compliance * diff);
  }
  return error;
}

/// eta_e^2 of a 6-node triangle on its own stiffness points: sigma* through the nodes (its
/// shape functions) against sigma_h where it was computed. The degree-4 rule integrates the quadratic sigma*
/// against the linear part of sigma_h exactly but for the weight r; the estimate needs no more.
template <class E, int S>
double triangle_cell_error(const Mat<6, 2>& x, const std::array<Vec<S>, 6>& node, const Vec<S>* at,
                           const Mat<S, S>& compliance) {
  double error = 0, det = 0;
  for (int q = 0; q < E::kStiffnessPoints; ++q) {
    const auto g = E::stiffness_point(x, q, det);
    Vec<S> diff  = -at[q];
    for (int c = 0; c < 6; ++c) diff += g.N(c) * node[c];
    error += g.weight * diff.dot(compliance * diff);
  }
  return error;
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

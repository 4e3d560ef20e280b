#pragma once
// Constexpr quadrature tables. Gauss points lie strictly inside an element, so r > 0 at every point
// even when element nodes sit on the axis (docs/theory.md 1.3: never use Lobatto or nodal rules).
#include <array>

namespace gapfe {

/// A rule on a reference cell: points (xi, eta) and weights.
template <int N>
struct Rule {
  std::array<std::array<double, 2>, N> point;
  std::array<double, N> weight;
};

namespace gauss {
/// 1-D Gauss-Legendre abscissae and weights on [-1, 1].
template <int N>
struct Line;
template <>
struct Line<1> {
  static constexpr std::array<double, 1> x{0.0}, w{2.0};
};
template <>
struct Line<2> {
  static constexpr double a = 0.57735026918962576451;  // 1/sqrt(3)
  static constexpr std::array<double, 2> x{-a, a}, w{1.0, 1.0};
};
template <>
struct Line<3> {
  static constexpr double a = 0.77459666924148337704;  // sqrt(3/5)
  static constexpr std::array<double, 3> x{-a, 0.0, a}, w{5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
};
template <>
struct Line<4> {
  static constexpr double a = 0.33998104358485626480, b = 0.86113631159405257522;
  static constexpr double wa = 0.65214515486254614263, wb = 0.34785484513745385737;
  static constexpr std::array<double, 4> x{-b, -a, a, b}, w{wb, wa, wa, wb};
};

/// Tensor-product rule on [-1, 1]^2, xi fastest.
template <int N>
constexpr Rule<N * N> square() {
  Rule<N * N> rule{};
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) {
      rule.point[j * N + i]  = {Line<N>::x[i], Line<N>::x[j]};
      rule.weight[j * N + i] = Line<N>::w[i] * Line<N>::w[j];
    }
  return rule;
}
}  // namespace gauss

namespace triangle_rule {
/// Area coordinates (L2, L3) on the reference triangle (0,0), (1,0), (0,1); weights sum to 1/2.
inline constexpr Rule<1> kCentroid{{{{1.0 / 3.0, 1.0 / 3.0}}}, {0.5}};
/// Strang-Fix 6-point rule, exact to degree 4 (all weights positive); used for body loads whose
/// integrand N_a r^2 is cubic on a straight triangle (docs/theory.md 4.1).
inline constexpr Rule<6> kDegree4{
    {{{0.445948490915965, 0.445948490915965},
      {0.445948490915965, 0.108103018168070},
      {0.108103018168070, 0.445948490915965},
      {0.091576213509771, 0.091576213509771},
      {0.091576213509771, 0.816847572980459},
      {0.816847572980459, 0.091576213509771}}},
    {0.5 * 0.223381589678011, 0.5 * 0.223381589678011, 0.5 * 0.223381589678011, 0.5 * 0.109951743655322,
     0.5 * 0.109951743655322, 0.5 * 0.109951743655322}};
}  // namespace triangle_rule

}  // namespace gapfe

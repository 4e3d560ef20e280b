#pragma once
// Tri6: 6-node quadratic isoparametric ring triangle, the 3-corner companion of Quad8 (an order-2 Gmsh mesh
// of triangles, or the triangles beside 8-node quadrilaterals). Displacements are quadratic, so it converges
// at the rate Quad8 does (displacement error O(h^3) in L2). Stiffness and load points: the Strang-Fix
// 6-point rule, exact to degree 4 and strictly inside the cell, so r > 0 at every point even with a side on
// the axis (docs/theory.md 1.3).
//
//   2                 corners 0, 1, 2 counterclockwise,
//   | .               mid-sides 3 (0-1), 4 (1-2), 5 (2-0): Gmsh's order of a 6-node triangle
//   5   4
//   |     .
//   0 -- 3 -- 1
#include "gapfe/element/isoparametric.hpp"
#include "gapfe/element/quadrature.hpp"

namespace gapfe {

struct Tri6 : Isoparametric<Tri6, 6, 6> {
  static constexpr int kNodes           = 6;
  static constexpr int kShapeNodes      = 6;
  static constexpr int kStiffnessPoints = 6;
  static constexpr int kLoadPoints      = 6;
  static constexpr int kEdgeNodes       = 3;  // (start, mid, end) at s = -1, 0, 1
  static constexpr std::array<std::array<int, 3>, 3> kEdges{{{0, 3, 1}, {1, 4, 2}, {2, 5, 0}}};
  /// The nodes in area coordinates (L2, L3) of the reference triangle (0, 0), (1, 0), (0, 1).
  static constexpr std::array<std::array<double, 2>, 6> kNodesRef{
      {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}}};
  static constexpr auto kRule = triangle_rule::kDegree4;  // (xi, eta) = (L2, L3); weights sum to 1/2
  using Degenerate            = Tri6;

  /// Shape functions at area coordinates (xi, eta) = (L2, L3), L1 = 1 - L2 - L3: corners L_i (2 L_i - 1),
  /// mid-sides 4 L_i L_j.
  static Vec<6> N(double xi, double eta) {
    const double l1 = 1 - xi - eta, l2 = xi, l3 = eta;
    Vec<6> n;
    n << l1 * (2 * l1 - 1), l2 * (2 * l2 - 1), l3 * (2 * l3 - 1), 4 * l1 * l2, 4 * l2 * l3, 4 * l3 * l1;
    return n;
  }
  static Mat<6, 2> dN(double xi, double eta) {
    const double l1 = 1 - xi - eta, l2 = xi, l3 = eta;
    Mat<6, 2> d;                  // d/dL2 and d/dL3, with dL1 = -dL2 - dL3
    d << 1 - 4 * l1, 1 - 4 * l1,  //
        4 * l2 - 1, 0,            //
        0, 4 * l3 - 1,            //
        4 * (l1 - l2), -4 * l2,   //
        4 * l3, 4 * l2,           //
        -4 * l3, 4 * (l1 - l3);
    return d;
  }
  /// The centroid (1/3, 1/3) with the reference triangle's area as weight: the full-ring volume estimate
  /// 2 pi r |J| / 2.
  static PointGeometry<6> centroid_point(const Mat<6, 2>& x, double& det) {
    return at(x, 1.0 / 3.0, 1.0 / 3.0, 0.5, det);
  }
};

}  // namespace gapfe

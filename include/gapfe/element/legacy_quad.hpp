#pragma once
// LegacyQuad: the SAAS-family quadrilateral (Wilson 1965), four constant-strain ring triangles around
// a centre node that is condensed out (docs/theory.md 2). Kept faithful so legacy answers can be compared:
//
//   3 ------- 2      corners 0..3 counterclockwise (0-based), centre node 4 at the corner average;
//   | \  2  / |      sub-triangles (0,1,4), (1,2,4), (2,3,4), (3,0,4), each a CST whose hoop term
//   |  3 4  1 |      N/r is evaluated at its centroid (one point per triangle, weight 2 pi rbar A_t).
//   | /  0  \ |      The 15x15 (3 DOF) or 10x10 (2 DOF) matrix is condensed to the corners by the
//   0 ------- 1      element kernel (K* = Kcc - Kci Kii^-1 Kic; seed's "12 degrees of freedom").
//
// The seed's COMMON /ARG/ RRR(5), ZZZ(5), S(15,15), BB(6,9) and TRISTF are this element [S].
#include "gapfe/element/point_maps.hpp"
#include "gapfe/element/quadrature.hpp"
#include "gapfe/element/tri3.hpp"

namespace gapfe {

struct LegacyQuad {
  static constexpr int kNodes           = 4;
  static constexpr int kShapeNodes      = 5;  // + the condensed centre node
  static constexpr int kStiffnessPoints = 4;  // one per sub-triangle
  static constexpr int kLoadPoints      = 4 * 6;
  static constexpr int kEdgeNodes       = 2;
  static constexpr std::array<std::array<int, 2>, 4> kEdges{{{0, 1}, {1, 2}, {2, 3}, {3, 0}}};
  static constexpr std::array<std::array<int, 3>, 4> kTriangles{{{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}};
  using Degenerate = Tri3;  // a 3-corner cell is a single CST: no centre node (docs/theory.md 2 item 7)

  /// Corners plus the centre node at their average.
  static Mat<5, 2> shape_coords(const Mat<4, 2>& x) {
    Mat<5, 2> y;
    y.topRows<4>() = x;
    y.row(4)       = 0.25 * x.colwise().sum();
    return y;
  }
  static PointGeometry<5> stiffness_point(const Mat<4, 2>& x, int q, double& det) {
    const auto& p = triangle_rule::kCentroid;
    return cst_point<5>(shape_coords(x), kTriangles[q], p.point[0][0], p.point[0][1], p.weight[0], det);
  }
  static PointGeometry<5> load_point(const Mat<4, 2>& x, int q, double& det) {
    const auto& p = triangle_rule::kDegree4;
    const int k   = q % 6;
    return cst_point<5>(shape_coords(x), kTriangles[q / 6], p.point[k][0], p.point[k][1], p.weight[k], det);
  }
  // No centroid_point: the element's centroid stress is the r-bar-A weighted mean of its four
  // sub-triangle stresses (docs/theory.md 2 item 4); the post-processor does that when this is absent.
};

}  // namespace gapfe

#pragma once
// Tri3: 3-node constant-strain ring triangle, for the 3-corner cells a structured grid leaves along
// boundary diagonals (docs/theory.md 2 item 7). The hoop term N/r is taken at the centroid, the classical
// one-point CST (the same approximation as each sub-triangle of LegacyQuad). Body loads use a
// degree-4 rule, exact for N_a r^2 (docs/theory.md 4.1).
//
//   2            local 0-based nodes 0, 1, 2, counterclockwise
//   |  .
//   0 -- 1
#include "gapfe/element/point_maps.hpp"
#include "gapfe/element/quadrature.hpp"

namespace gapfe {

struct Tri3 {
  static constexpr int kNodes           = 3;
  static constexpr int kShapeNodes      = 3;
  static constexpr int kStiffnessPoints = 1;
  static constexpr int kLoadPoints      = 6;
  static constexpr int kEdgeNodes       = 2;
  static constexpr std::array<std::array<int, 2>, 3> kEdges{{{0, 1}, {1, 2}, {2, 0}}};
  static constexpr std::array<int, 3> kTri{0, 1, 2};
  using Degenerate = Tri3;

  /// Coordinates of the shape nodes: the element has no interior nodes.
  static const Mat<3, 2>& shape_coords(const Mat<3, 2>& x) { return x; }
  static PointGeometry<3> stiffness_point(const Mat<3, 2>& x, int /*q*/, double& det) {
    const auto& p = triangle_rule::kCentroid;
    return cst_point<3>(x, kTri, p.point[0][0], p.point[0][1], p.weight[0], det);
  }
  static PointGeometry<3> load_point(const Mat<3, 2>& x, int q, double& det) {
    const auto& p = triangle_rule::kDegree4;
    return cst_point<3>(x, kTri, p.point[q][0], p.point[q][1], p.weight[q], det);
  }
  static PointGeometry<3> centroid_point(const Mat<3, 2>& x, double& det) {
    return stiffness_point(x, 0, det);
  }
};

}  // namespace gapfe

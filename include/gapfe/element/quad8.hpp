#pragma once
// Quad8: 8-node serendipity quadrilateral, 3x3 Gauss, for accuracy (displacement error O(h^3)), with
// B-bar on a pressure linear in each cell (1, r, z: assembly/element_kernel.hpp): measured not to lock near
// incompressibility, and to keep its second-order stresses where the pressure varies, which a constant
// pressure would not (docs/theory.md 1.2; docs/accuracy.md "Near incompressibility", with what that rests
// on).
//
//   4 -- 7 -- 3      corners 0..3 counterclockwise as Quad4 (0-based: 1 -> 0 ...),
//   |         |      mid-sides 4 (0-1), 5 (1-2), 6 (2-3), 7 (3-0)
//   8         6      (drawn 1-based: 5..8)
//   |         |
//   1 -- 5 -- 2
#include "gapfe/element/isoparametric.hpp"
#include "gapfe/element/quadrature.hpp"
#include "gapfe/element/tri6.hpp"

namespace gapfe {

struct Quad8 : Isoparametric<Quad8, 8, 9> {
  static constexpr int kNodes           = 8;
  static constexpr int kShapeNodes      = 8;
  static constexpr int kStiffnessPoints = 9;
  static constexpr int kLoadPoints      = 9;
  static constexpr int kPressureModes   = 3;
  static constexpr int kEdgeNodes       = 3;  // (start, mid, end) at s = -1, 0, 1
  static constexpr std::array<std::array<int, 3>, 4> kEdges{{{0, 4, 1}, {1, 5, 2}, {2, 6, 3}, {3, 7, 0}}};
  static constexpr std::array<std::array<double, 2>, 8> kNodesRef{
      {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}}};
  static constexpr auto kRule = gauss::square<3>();
  using Degenerate            = Tri6;  // what a 3-corner cell of a Quad8 mesh becomes

  static Vec<8> N(double xi, double eta) {
    Vec<8> n;
    for (int a = 0; a < 4; ++a) {
      const double xa = kNodesRef[a][0], ya = kNodesRef[a][1];
      n(a) = 0.25 * (1 + xa * xi) * (1 + ya * eta) * (xa * xi + ya * eta - 1);
    }
    for (int a = 4; a < 8; ++a) {
      const double xa = kNodesRef[a][0], ya = kNodesRef[a][1];
      n(a) = xa == 0 ? 0.5 * (1 - xi * xi) * (1 + ya * eta) : 0.5 * (1 + xa * xi) * (1 - eta * eta);
    }
    return n;
  }
  static Mat<8, 2> dN(double xi, double eta) {
    Mat<8, 2> d;
    for (int a = 0; a < 4; ++a) {
      const double xa = kNodesRef[a][0], ya = kNodesRef[a][1];
      d(a, 0) = 0.25 * xa * (1 + ya * eta) * (2 * xa * xi + ya * eta);
      d(a, 1) = 0.25 * ya * (1 + xa * xi) * (xa * xi + 2 * ya * eta);
    }
    for (int a = 4; a < 8; ++a) {
      const double xa = kNodesRef[a][0], ya = kNodesRef[a][1];
      if (xa == 0) {
        d(a, 0) = -xi * (1 + ya * eta);
        d(a, 1) = 0.5 * ya * (1 - xi * xi);
      } else {
        d(a, 0) = 0.5 * xa * (1 - eta * eta);
        d(a, 1) = -eta * (1 + xa * xi);
      }
    }
    return d;
  }
};

}  // namespace gapfe

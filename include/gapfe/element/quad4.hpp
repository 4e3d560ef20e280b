#pragma once
// Quad4: 4-node bilinear isoparametric quadrilateral, 2x2 Gauss (docs/theory.md 1.2).
//
//   4 ---- 3     eta        nodes counterclockwise from the corner nearest the origin
//   |      |      ^         (seed Fig. 1: IX(N,1..4) = (I,J), (I+1,J), (I+1,J+1), (I,J+1))
//   1 ---- 2      +--> xi   local numbering here is 0-based: 0, 1, 2, 3
#include "gapfe/element/isoparametric.hpp"
#include "gapfe/element/quadrature.hpp"
#include "gapfe/element/tri3.hpp"

namespace gapfe {

struct Quad4 : Isoparametric<Quad4, 4, 4> {
  static constexpr int kNodes           = 4;
  static constexpr int kShapeNodes      = 4;  // no condensed interior nodes
  static constexpr int kStiffnessPoints = 4;
  static constexpr int kLoadPoints      = 4;  // 2x2 Gauss integrates N_a r^2 exactly on parallelograms
  static constexpr int kEdgeNodes       = 2;
  static constexpr std::array<std::array<int, 2>, 4> kEdges{{{0, 1}, {1, 2}, {2, 3}, {3, 0}}};
  static constexpr std::array<std::array<double, 2>, 4> kCorners{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
  static constexpr auto kRule = gauss::square<2>();
  using Degenerate            = Tri3;  // what a 3-corner cell of a Quad4 mesh becomes

  static Vec<4> N(double xi, double eta) {
    Vec<4> n;
    for (int a = 0; a < 4; ++a) n(a) = 0.25 * (1 + kCorners[a][0] * xi) * (1 + kCorners[a][1] * eta);
    return n;
  }
  static Mat<4, 2> dN(double xi, double eta) {
    Mat<4, 2> d;
    for (int a = 0; a < 4; ++a) {
      d(a, 0) = 0.25 * kCorners[a][0] * (1 + kCorners[a][1] * eta);
      d(a, 1) = 0.25 * kCorners[a][1] * (1 + kCorners[a][0] * xi);
    }
    return d;
  }
};

/// Quad4 with B-bar: the volumetric strain is the element's mean, one pressure mode
/// (assembly/element_kernel.hpp). Plain Quad4 locks when the flow is near-incompressible (nu -> 1/2, and
/// fully plastic Hill/Mises flow, which is isochoric); this one does not (tests/test_plasticity.cpp
/// measures both).
struct Quad4BBar : Quad4 {
  static constexpr int kPressureModes = 1;
};

}  // namespace gapfe

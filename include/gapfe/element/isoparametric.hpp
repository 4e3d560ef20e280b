#pragma once
// Isoparametric<Shape, NN, NQ>: the point evaluations every Gauss-integrated isoparametric element
// shares, given its shape functions Shape::N, Shape::dN and rule Shape::kRule (NQ points). Quad4 and
// Quad8 derive from it; stiffness and load points use the same rule, the centroid is (0, 0).
#include "gapfe/element/point_maps.hpp"

namespace gapfe {

template <class Shape, int NN, int NQ>
struct Isoparametric {
  static PointGeometry<NN> at(const Mat<NN, 2>& x, double xi, double eta, double w, double& det) {
    return isoparametric_point<NN>(x, Shape::N(xi, eta), Shape::dN(xi, eta), w, det);
  }
  /// Coordinates of the shape nodes: isoparametric elements have no interior nodes.
  static const Mat<NN, 2>& shape_coords(const Mat<NN, 2>& x) { return x; }
  static PointGeometry<NN> stiffness_point(const Mat<NN, 2>& x, int q, double& det) {
    return at(x, Shape::kRule.point[q][0], Shape::kRule.point[q][1], Shape::kRule.weight[q], det);
  }
  static PointGeometry<NN> load_point(const Mat<NN, 2>& x, int q, double& det) {
    return stiffness_point(x, q, det);
  }
  /// Reference centroid (xi = eta = 0), weight = the full-ring volume estimate 2 pi r |J| 4.
  static PointGeometry<NN> centroid_point(const Mat<NN, 2>& x, double& det) { return at(x, 0, 0, 4.0, det); }
};

}  // namespace gapfe

#pragma once
// Superconvergent patch recovery (Zienkiewicz and Zhu 1992; docs/accuracy.md): the least-squares sums of a
// polynomial through the stresses at the stiffness points of the cells around a node, per material, and its
// value at the node. The error estimate (post/error_estimate.hpp) reads them.
#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include <Eigen/LU>

#include "gapfe/core/types.hpp"

namespace gapfe::detail {

/// Recovery slots: one per node and material around it (most nodes have one).
class RecoverySlots {
 public:
  explicit RecoverySlots(int nodes) : first_(static_cast<std::size_t>(nodes), -1) {}
  void add(int node, int material) {
    int& first = first_[static_cast<std::size_t>(node)];
    if (first < 0)
      first = material;
    else if (first != material)
      more_.push_back({node, material});
  }
  void finish() {
    std::sort(more_.begin(), more_.end());
    more_.erase(std::unique(more_.begin(), more_.end()), more_.end());
  }
  std::size_t size() const { return first_.size() + more_.size(); }
  /// The node of slot `k`; -1: a node no recovered cell touches.
  int node(std::size_t k) const {
    return k < first_.size() ? (first_[k] >= 0 ? static_cast<int>(k) : -1) : more_[k - first_.size()][0];
  }
  std::size_t operator()(int node, int material) const {
    if (first_[static_cast<std::size_t>(node)] == material) return static_cast<std::size_t>(node);
    const auto it = std::lower_bound(more_.begin(), more_.end(), std::array<int, 2>{node, material});
    return first_.size() + static_cast<std::size_t>(it - more_.begin());
  }

 private:
  std::vector<int> first_;                ///< the first material seen at each node, -1: none
  std::vector<std::array<int, 2>> more_;  ///< (node, material) of the others, sorted
};

/// A patch's least-squares sums for a polynomial in (r - r_n, z - z_n) about its node: a plane (P = 3 terms:
/// 1, dr, dz) for linear cells, a quadratic (P = 6: also dr^2, dr dz, dz^2) for quadratic ones; the sums over
/// its points of p p^T and p sigma^T, p the terms at the point.
template <int S, int P = 3>
struct PatchSums {
  static_assert(P == 3 || P == 6, "a plane or a quadratic");
  Mat<P, P> normal = Mat<P, P>::Zero();
  Mat<P, S> right  = Mat<P, S>::Zero();
  static Vec<P> terms(const Vec2& d) {
    Vec<P> p;
    if constexpr (P == 3)
      p << 1.0, d(0), d(1);
    else
      p << 1.0, d(0), d(1), d(0) * d(0), d(0) * d(1), d(1) * d(1);
    return p;
  }
  /// One point at `offset` = point - node.
  void add(const Vec2& offset, const Vec<S>& stress) {
    const Vec<P> p = terms(offset);
    normal += p * p.transpose();
    right += p * stress.transpose();
  }
  /// A cell's plane sums about another origin, `shift` = that origin - this node: p = T p' with
  /// T = [1 0 0; shift I].
  void add_shifted(const PatchSums& cell, const Vec2& shift) requires(P == 3) {
    Mat<3, 3> m = cell.normal;  // T m T^T, by rows then by columns
    m.row(1) += shift(0) * m.row(0), m.row(2) += shift(1) * m.row(0);
    m.col(1) += shift(0) * m.col(0), m.col(2) += shift(1) * m.col(0);
    normal += m;
    right.row(0) += cell.right.row(0);
    right.row(1) += cell.right.row(1) + shift(0) * cell.right.row(0);
    right.row(2) += cell.right.row(2) + shift(1) * cell.right.row(0);
  }
  /// The fitted value at the node, c0: of the full polynomial, else of the plane (the leading 3 x 3 block
  /// holds the plane's sums), else the points' mean.
  Vec<S> at_node() const { return (node_row().transpose() * right).transpose(); }
  /// The row `a` with at_node() = (a^T right)^T, from the normal sums alone. The fit is linear in the
  /// stresses: a point's share in the value at the node is a^T terms(offset), which depends on where the
  /// points lie only (post/recovery_weights.hpp keeps them for a mesh).
  Vec<P> node_row() const {
    Vec<P> row         = Vec<P>::Zero();
    const double count = normal(0, 0);
    if (count <= 0) return row;
    if constexpr (P == 6) {
      if (count >= 6) {
        // The quadratic's monomials make the scaled matrix's determinant fall with a cell's skew (5e-11 at
        // 18 degrees) while c0 stays as well determined: accept by rank and by c0's variance factor,
        // (S^-1)_00, which is 3 in an interior patch and 21 at a corner with one cell, skewed or not.
        const auto [d, scaled] = scaled_normal<6>();
        Eigen::FullPivLU<Mat<6, 6>> lu(scaled);
        lu.setThreshold(1e-12);
        if (lu.rank() == 6) {
          const Mat<6, 6> inverse = lu.inverse();
          if (inverse(0, 0) < 1e4) return d(0) * (inverse.row(0) * d.asDiagonal()).transpose();
        }
      }
    }
    if (count >= 3) {  // a well-spread plane's scaled determinant is of order 1
      const auto [d, scaled] = scaled_normal<3>();
      if (scaled.determinant() > 1e-6) {
        row.template head<3>() = d(0) * (scaled.inverse().row(0) * d.asDiagonal()).transpose();
        return row;
      }
    }
    row(0) = 1 / count;
    return row;
  }
  /// The fitted plane's value at `offset` from the node, when its points span a plane (a neighbour's patch
  /// read at a boundary node: post/peak_stress.hpp); false otherwise. `leverage`, when given, receives the
  /// variance factor of the value at the node itself, (S^-1)_00 of the scaled sums: 1 at the centre of
  /// symmetric points, 1 plus the node's squared Mahalanobis distance from their mean in general: it
  /// grows as the node lies outside them (the plane extrapolated).
  bool plane_at(const Vec2& offset, Vec<S>& value, double* leverage = nullptr) const requires(P == 3) {
    if (normal(0, 0) < 3) return false;
    const auto [d, scaled] = scaled_normal<3>();
    if (!(scaled.determinant() > 1e-6)) return false;
    const Mat<3, 3> inverse = scaled.inverse();
    const Mat<3, S> c       = d.asDiagonal() * (inverse * (d.asDiagonal() * right));
    value                   = (terms(offset).transpose() * c).transpose();
    if (leverage) *leverage = inverse(0, 0);
    return true;
  }

 private:
  /// The first Q terms' normal matrix scaled to a unit diagonal, D N D, with D.
  template <int Q>
  std::pair<Vec<Q>, Mat<Q, Q>> scaled_normal() const {
    const Vec<Q> d =
        normal.template topLeftCorner<Q, Q>().diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    return {d, d.asDiagonal() * normal.template topLeftCorner<Q, Q>() * d.asDiagonal()};
  }
};

}  // namespace gapfe::detail

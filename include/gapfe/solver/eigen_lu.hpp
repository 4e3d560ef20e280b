#pragma once
// EigenLu: Eigen's SparseLU (supernodal, COLAMD column ordering) on the full matrix, the header-only
// solver for unsymmetric stiffnesses, next to the symmetric EigenLdlt and CHOLMOD: what a tangent that
// loses symmetry needs (friction's slip, docs/theory.md 6; measured against a symmetrised tangent in
// BENCHMARKS.md "Unsymmetric against symmetrized tangent"). It reads full storage (kStorage), so a model with
// it assembles every entry. analyze() once per pattern, factorize() per matrix. A singular matrix is detected
// from U's pivots, as EigenLdlt does from D's: factorize() returns false and failure() says why, never a NaN
// solution.
#include <cmath>
#include <string>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseLU>

#include "gapfe/core/concepts.hpp"

namespace gapfe {

class EigenLu {
 public:
  static constexpr const char* kName      = "Eigen SparseLU (COLAMD)";
  static constexpr MatrixStorage kStorage = MatrixStorage::full;
  /// Pivots below this fraction of the largest pivot mean a singular system (rigid-body mode).
  double singular_pivot_ratio = 1e-13;

  void analyze(const SpMat& k) { lu_.analyzePattern(k); }
  bool factorize(const SpMat& k) {
    lu_.factorize(k);
    failure_.clear();
    failed_equation_ = -1;
    if (lu_.info() != Eigen::Success)
      return fail("stiffness is singular (" + lu_.lastErrorMessage() + ")", -1);
    // U's diagonal is kept in the supernodes of L (as SparseLU::absDeterminant reads it).
    double largest = 0, smallest = INFINITY;
    Eigen::Index worst = 0;
    const auto& l      = lu_.matrixL().m_mapL;
    for (Eigen::Index j = 0; j < l.cols(); ++j)
      for (typename std::decay_t<decltype(l)>::InnerIterator it(l, j); it; ++it)
        if (it.index() == j) {
          const double pivot = std::abs(it.value());
          if (!std::isfinite(pivot)) return fail("non-finite pivot", -1);
          largest = std::max(largest, pivot);
          if (pivot < smallest) smallest = pivot, worst = j;
          break;
        }
    if (!(smallest > singular_pivot_ratio * largest))
      return fail("stiffness is singular", static_cast<int>(lu_.colsPermutation().indices()(worst)));
    return true;
  }
  VecX solve(const VecX& b) const { return lu_.solve(b); }
  const std::string& failure() const { return failure_; }
  int failed_equation() const { return failed_equation_; }

 private:
  bool fail(const std::string& what, int eq) {
    failure_         = what;
    failed_equation_ = eq;
    return false;
  }
  Eigen::SparseLU<SpMat, Eigen::COLAMDOrdering<int>> lu_;
  std::string failure_;
  int failed_equation_ = -1;
};

static_assert(LinearSolver<EigenLu>);

}  // namespace gapfe

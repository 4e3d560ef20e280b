#pragma once
// EigenLdlt: the embedded default, Eigen's SimplicialLDLT on the lower triangle, nested-dissection ordering.
// analyze() once per pattern, factorize() per matrix. A singular or indefinite stiffness (a missing
// constraint, an inverted element) is detected from the pivots, not left to produce huge or NaN
// displacements: factorize() returns false and failure() names the equation of the worst pivot.
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#include "gapfe/core/concepts.hpp"
#include "gapfe/solver/nested_dissection.hpp"

namespace gapfe {

/// An Eigen ordering functor that returns the caller's elimination order when one is set in `slot` (for
/// the duration of one analyzePattern: Eigen default-constructs the functor inside it, so the order
/// cannot travel in the object), else the Fallback's.
template <class Fallback>
struct GivenOrFallbackOrdering {
  static inline thread_local const std::vector<int>* slot = nullptr;
  template <class MatrixType, class Permutation>
  void operator()(const MatrixType& c, Permutation& perm) const {
    if (slot == nullptr || static_cast<Eigen::Index>(slot->size()) != c.cols()) return Fallback{}(c, perm);
    perm.resize(c.cols());
    for (Eigen::Index k = 0; k < c.cols(); ++k)
      perm.indices()[k] =
          static_cast<typename Permutation::StorageIndex>((*slot)[static_cast<std::size_t>(k)]);
  }
};

/// Ordering: NestedDissectionOrdering (default; fewer operations on gapfe's 2-D meshes, BENCHMARKS.md)
/// or Eigen::AMDOrdering<int>.
template <class Ordering>
class EigenLdltWith {
 public:
  static constexpr const char* kName = std::is_same_v<Ordering, NestedDissectionOrdering>
                                           ? "Eigen SimplicialLDLT (nested dissection)"
                                           : "Eigen SimplicialLDLT (AMD)";
  /// Pivots below this fraction of the largest pivot mean a singular system (rigid-body mode).
  double singular_pivot_ratio = 1e-13;

  void analyze(const SpMat& k) { ldlt_.analyzePattern(k); }
  /// The caller's elimination order (order[k] = the equation eliminated k-th; the drivers pass the mesh's
  /// coordinate nested dissection, solver/coordinate_dissection.hpp). The nested-dissection policy only:
  /// the AMD one stays AMD, for comparisons.
  void analyze(const SpMat& k,
               const std::vector<int>& order) requires std::is_same_v<Ordering, NestedDissectionOrdering> {
    Given::slot = &order;
    ldlt_.analyzePattern(k);
    Given::slot = nullptr;
  }
  bool factorize(const SpMat& k) {
    ldlt_.factorize(k);
    failure_.clear();
    if (ldlt_.info() != Eigen::Success) return fail("stiffness is singular (zero pivot)", -1);
    const VecX& d      = ldlt_.vectorD();
    Eigen::Index worst = 0;
    const double dmax  = d.cwiseAbs().maxCoeff();
    const double dmin  = d.minCoeff(&worst);
    if (!std::isfinite(dmax) || !std::isfinite(dmin)) return fail("non-finite pivot", -1);
    if (dmin <= singular_pivot_ratio * dmax) {
      const int eq = ldlt_.permutationPinv().indices()(worst);
      return fail(dmin <= 0 && dmin < -singular_pivot_ratio * dmax ? "stiffness is not positive definite"
                                                                   : "stiffness is singular",
                  eq);
    }
    return true;
  }
  VecX solve(const VecX& b) const { return ldlt_.solve(b); }
  const std::string& failure() const { return failure_; }
  int failed_equation() const { return failed_equation_; }

 private:
  bool fail(const std::string& what, int eq) {
    failure_         = what;
    failed_equation_ = eq;
    return false;
  }
  using Given = GivenOrFallbackOrdering<Ordering>;
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower, Given> ldlt_;
  std::string failure_;
  int failed_equation_ = -1;
};
using EigenLdlt    = EigenLdltWith<NestedDissectionOrdering>;
using EigenLdltAmd = EigenLdltWith<Eigen::AMDOrdering<int>>;
static_assert(OrderedSolver<EigenLdlt>);
static_assert(!OrderedSolver<EigenLdltAmd>);
static_assert(LinearSolver<EigenLdltAmd>);

}  // namespace gapfe

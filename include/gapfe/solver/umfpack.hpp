#pragma once
// UmfpackLu: UMFPACK's unsymmetric multifrontal LU (SuiteSparse) through Eigen/UmfPackSupport, on full
// storage: the faster unsymmetric path next to the header-only EigenLu, for friction's slip tangent.
// analyze() runs UMFPACK's symbolic analysis (COLAMD ordering) once per pattern; factorize() only the
// numeric factorization. UMFPACK is GPL, so like CHOLMOD this header is opt-in: not in gapfe.hpp, and it
// needs the gapfe::umfpack CMake target (GAPFE_HAS_UMFPACK). A matrix UMFPACK finds exactly singular is
// refused (its status is a warning, not an error, so it is checked here), and so is one whose smallest
// pivot is below singular_pivot_ratio of the largest (a rigid-body mode in round-off), naming its column.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/UmfPackSupport>

#include "gapfe/core/concepts.hpp"

namespace gapfe {

class UmfpackLu {
 public:
  static constexpr const char* kName      = "UMFPACK LU (SuiteSparse)";
  static constexpr MatrixStorage kStorage = MatrixStorage::full;
  /// Pivots below this fraction of the largest (of the row-scaled matrix UMFPACK factorizes) mean a
  /// singular system (rigid-body mode), as in EigenLu.
  double singular_pivot_ratio = 1e-13;

  void analyze(const SpMat& k) { lu_.analyzePattern(k); }
  bool factorize(const SpMat& k) {
    lu_.factorize(k);
    failure_.clear();
    failed_equation_ = -1;
    // U's diagonal and the column order, also after UMFPACK's "singular" warning (Numeric is kept).
    const int n = static_cast<int>(k.cols());
    pivots_.resize(n), columns_.resize(n);
    if (lu_.numeric() == nullptr ||
        umfpack_di_get_numeric(nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, columns_.data(),
                               pivots_.data(), nullptr, nullptr, lu_.numeric()) != UMFPACK_OK) {
      failure_ = "stiffness is singular (UMFPACK)";
      return false;
    }
    double largest = 0, smallest = INFINITY;
    int worst = -1;
    for (int j = 0; j < n; ++j) {
      const double pivot = std::abs(pivots_[j]);
      if (!std::isfinite(pivot)) {
        failure_ = "non-finite pivot (UMFPACK)";
        return false;
      }
      largest = std::max(largest, pivot);
      if (pivot < smallest) smallest = pivot, worst = j;
    }
    if (lu_.info() != Eigen::Success || !(smallest > singular_pivot_ratio * largest)) {
      failure_         = "stiffness is singular (UMFPACK)";
      failed_equation_ = worst >= 0 ? columns_[worst] : -1;
      return false;
    }
    return true;
  }
  VecX solve(const VecX& b) const { return lu_.solve(b); }
  const std::string& failure() const { return failure_; }
  /// After a failed factorize(): the column (equation) of the smallest pivot, -1 when unknown.
  int failed_equation() const { return failed_equation_; }

 private:
  struct Lu : Eigen::UmfPackLU<SpMat> {
    void* numeric() const { return m_numeric; }
  };
  Lu lu_;
  std::string failure_;
  int failed_equation_ = -1;
  std::vector<double> pivots_;
  std::vector<int> columns_;
};

static_assert(LinearSolver<UmfpackLu>);

}  // namespace gapfe

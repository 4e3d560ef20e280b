#pragma once
// UmfpackLu: UMFPACK's unsymmetric multifrontal LU (SuiteSparse) through Eigen/UmfPackSupport, on full
// storage: the faster unsymmetric path next to the header-only EigenLu, for friction's slip tangent.
// analyze() runs UMFPACK's symbolic analysis (COLAMD ordering) once per pattern; factorize() only the
// numeric factorization. UMFPACK is GPL, so like CHOLMOD this header is opt-in: not in gapfe.hpp, and it
// needs the gapfe::umfpack CMake target (GAPFE_HAS_UMFPACK). A matrix UMFPACK finds exactly singular is
// refused (its status is a warning, not an error, so it is checked here); UMFPACK does not expose its
// condition estimate through Eigen, so a nearly singular one shows as a large residual instead.
#include <string>

#include <Eigen/UmfPackSupport>

#include "gapfe/core/concepts.hpp"

namespace gapfe {

class UmfpackLu {
 public:
  static constexpr const char* kName      = "UMFPACK LU (SuiteSparse)";
  static constexpr MatrixStorage kStorage = MatrixStorage::full;

  void analyze(const SpMat& k) { lu_.analyzePattern(k); }
  bool factorize(const SpMat& k) {
    lu_.factorize(k);
    failure_.clear();
    if (lu_.info() != Eigen::Success) {
      failure_ = "stiffness is singular (UMFPACK)";
      return false;
    }
    return true;
  }
  VecX solve(const VecX& b) const { return lu_.solve(b); }
  const std::string& failure() const { return failure_; }
  int failed_equation() const { return -1; }

 private:
  Eigen::UmfPackLU<SpMat> lu_;
  std::string failure_;
};

static_assert(LinearSolver<UmfpackLu>);

}  // namespace gapfe

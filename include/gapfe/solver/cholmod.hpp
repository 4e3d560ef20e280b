#pragma once
// CholmodLlt: CHOLMOD supernodal Cholesky (SuiteSparse) through Eigen/CholmodSupport, the symbolic
// analysis done once per pattern. The elimination order is the caller's when it gives one
// (analyze(K, order): the drivers pass the mesh's coordinate nested dissection, which on the 1e6-equation
// tube needs a third of AMD's flops, BENCHMARKS.md), else AMD. CHOLMOD is GPL, so this header is
// opt-in: it is not in gapfe.hpp, and needs the gapfe::cholmod CMake target (GAPFE_HAS_CHOLMOD).
// Link BLAS from OpenBLAS: the supernodal factorization is BLAS-3 bound, several times slower on the
// reference BLAS.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/CholmodSupport>

#include "gapfe/core/concepts.hpp"
#include "gapfe/core/workers.hpp"
#include "gapfe/solver/cholmod_factor.hpp"
#include "gapfe/solver/split_cholmod.hpp"
#include "gapfe/solver/threads.hpp"

namespace gapfe {

namespace detail {

/// CHOLMOD's malloc once a program asks for it (touch_cholmod_blocks_on_workers): a block of 64 MiB or more,
/// the factor's values, gets its pages touched on every thread of the pool (core/workers.hpp) before CHOLMOD
/// writes it. The kernel zeroes each page at its first touch, about 2 s per GB on the machine of
/// BENCHMARKS.md, a third of the factorization at 1e6 equations when CHOLMOD's own clearing does it on one
/// thread. With one thread this is malloc. No value changes: CHOLMOD writes every entry it reads.
inline void* touched_malloc(std::size_t size) noexcept {
  constexpr std::size_t kTouched = std::size_t(64) << 20, kPiece = std::size_t(2) << 20, kPage = 4096;
  void* block = std::malloc(size);
  if (block == nullptr || size < kTouched || worker_threads() < 2) return block;
  auto* bytes = static_cast<volatile char*>(block);
  try {  // CHOLMOD is C: nothing may leave this function but the block
    parallel_for((size + kPiece - 1) / kPiece, [&](std::size_t piece) {
      for (std::size_t at = piece * kPiece, end = std::min(size, at + kPiece); at < end; at += kPage)
        bytes[at] = 0;
    });
  } catch (...) {  // pages not touched now are touched by CHOLMOD's clearing
  }
  return block;
}

}  // namespace detail

/// From now on CHOLMOD allocates through detail::touched_malloc, unless its malloc (SuiteSparse_config's,
/// process-wide) is already another than the C library's. For programs to call, like set_solver_threads
/// (solver/threads.hpp): the `gapfe` command does.
inline void touch_cholmod_blocks_on_workers() {
  if (SuiteSparse_config.malloc_func == &std::malloc)
    SuiteSparse_config.malloc_func = &detail::touched_malloc;
}

class CholmodLlt {
 public:
  static constexpr const char* kName = "CHOLMOD supernodal LLT";
  /// Reciprocal condition estimates below this mean a singular system.
  double singular_rcond = 1e-14;
  /// Systems of at least this many equations, analyzed in an order with a top separator (a nested
  /// dissection's), are factorized as two halves on two threads and the separator (SplitCholmod,
  /// solver/split_cholmod.hpp), on any number of threads, so that the factor is the same on any. Below,
  /// the halves are too small to be worth the separator's dense work.
  Eigen::Index split_from = 40000;

  CholmodLlt() = default;
  void analyze(const SpMat& k) {
    split_.reset();
    whole_ = true;
    detail::relax_supernodes(llt_.cholmod(), k.rows());
    llt_.analyzePattern(k);
  }
  /// The symbolic analysis in the caller's elimination order (order[k] = the equation eliminated k-th).
  void analyze(const SpMat& k, const std::vector<int>& order) {
    split_.reset();
    whole_ = true;
    order_.clear();
    llt_.release();
    detail::relax_supernodes(llt_.cholmod(), k.rows());
    if (k.rows() >= split_from) {
      auto split = std::make_unique<SplitCholmod>();
      if (split->analyze(k, order)) {
        split_ = std::move(split);
        order_ = order;  // for a factorization re-done whole (factorize)
        return;
      }
    }
    llt_.analyze_in(k, order);
  }
  bool factorize(const SpMat& k) {
    failure_.clear();
    failed_equation_ = -1;
    whole_           = split_ == nullptr;
    // A split whose halves or separator are not positive definite, or which estimates a tiny rcond, is
    // dropped for the rest of this analysis and the factorization re-done whole: that one says what is
    // wrong and where (weakest_equation), and stands in for the split when it succeeds after all.
    if (split_) {
      if (split_->factorize(k) && split_->rcond() > singular_rcond) return true;
      split_.reset();  // its factors freed before the whole one is made
      whole_ = true;
      llt_.analyze_in(k, order_);
      if (llt_.factor() == nullptr) return fail("CHOLMOD could not analyze the stiffness (out of memory?)");
    }
    {
      // OpenBLAS's threads (set_solver_threads) share only the large supernodes of large systems: on the
      // 1e5-equation tubes two threads factorized no faster, often slower, and left a thread spinning
      // against gapfe's own after every factorization of a Newton run (BENCHMARKS.md "Every core:
      // --threads"). So up to kLargeSystem equations the factor is the same on any number of threads, and
      // so is one that stands in for a dropped split (order_ kept), as the split's was.
      const OneBlasThread small(k.rows() <= detail::kLargeSystem || !order_.empty());
      llt_.factorize(k);
    }
    if (llt_.info() != Eigen::Success) {
      failed_equation_ = weakest_equation();
      return fail("stiffness is singular or not positive definite (CHOLMOD)");
    }
    const double rcond = cholmod_rcond(llt_.factor(), &llt_.cholmod());
    if (!(rcond > singular_rcond)) {
      failed_equation_ = weakest_equation();
      char text[64];
      std::snprintf(text, sizeof text, "stiffness is singular (CHOLMOD rcond %.3g)", rcond);
      return fail(text);
    }
    return true;
  }
  /// On one OpenBLAS thread: a solve's BLAS-2 calls were no faster on two (tube-1e6: 0.42 s on one, 0.45
  /// s on two), and woke OpenBLAS's threads to spin against gapfe's own.
  VecX solve(const VecX& b) const {
    if (split_ && !whole_) return split_->solve(b);
    const OneBlasThread one(true);
    return llt_.solve(b);
  }
  /// The last analysis' flop count and factor size (cholmod_common fl, lnz) and the values the last
  /// factorization stores (the relaxed supernodes' zeros included); a split's (SplitCholmod::statistics)
  /// when the last factorization was one.
  FactorStatistics statistics() {
    if (split_ && !whole_) return split_->statistics();
    const cholmod_factor* f = llt_.factor();
    return {llt_.cholmod().fl, llt_.cholmod().lnz, f != nullptr ? static_cast<double>(f->xsize) : 0.0};
  }
  /// Whether the last factorization was split (SplitCholmod), and its separator's equations.
  bool split() const { return split_ && !whole_; }
  int split_separator() const { return split() ? split_->separator_size() : 0; }
  const std::string& failure() const { return failure_; }
  /// After a failed factorize(): the equation (caller's numbering) where L's pivot broke down (CHOLMOD's
  /// `minor`) or, when every pivot was positive but the condition estimate too small, the one with the
  /// smallest pivot: a rigid-body mode's last free DOF in the elimination order. -1 when unknown.
  int failed_equation() const { return failed_equation_; }

 private:
  /// See failed_equation(); Perm maps L's columns to the matrix's.
  int weakest_equation() {
    const cholmod_factor* f = llt_.factor();
    if (f == nullptr || f->Perm == nullptr || f->x == nullptr || f->itype != CHOLMOD_INT) return -1;
    const int* perm = static_cast<const int*>(f->Perm);
    if (f->minor < f->n) return perm[f->minor];
    if (!f->is_super) return -1;
    double smallest = INFINITY;
    int worst       = -1;
    detail::for_each_factor_column(*f, [&](int j, const int*, const double* x, int) {
      if (const double d = std::abs(x[0]); d < smallest) smallest = d, worst = j;
    });
    return worst >= 0 ? perm[worst] : -1;
  }
  bool fail(const std::string& what) {
    failure_ = what;
    return false;
  }
  detail::CholmodFactor llt_;
  std::unique_ptr<SplitCholmod> split_;  ///< the halves and separator, when analyze found a split
  std::vector<int> order_;               ///< the split's order, for a factorization re-done whole
  bool whole_ = true;                    ///< the last factorization (or analysis) is llt_'s, not split_'s
  std::string failure_;
  int failed_equation_ = -1;
};
static_assert(OrderedSolver<CholmodLlt>);

}  // namespace gapfe

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
#include <string>
#include <vector>

#include <Eigen/CholmodSupport>

#include "gapfe/core/concepts.hpp"
#include "gapfe/core/workers.hpp"
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

  CholmodLlt() {
    cholmod_common& c    = llt_.cholmod();
    c.nmethods           = 1;
    c.method[0].ordering = CHOLMOD_AMD;
    c.postorder          = 1;
    c.supernodal         = CHOLMOD_SUPERNODAL;
    c.print              = 0;  // failures are reported through failure(), not printed by CHOLMOD
  }
  void analyze(const SpMat& k) {
    relax_supernodes(k.rows());
    llt_.analyzePattern(k);
  }
  /// The symbolic analysis in the caller's elimination order (order[k] = the equation eliminated k-th).
  void analyze(const SpMat& k, const std::vector<int>& order) {
    relax_supernodes(k.rows());
    llt_.analyze_in(k, order);
  }
  bool factorize(const SpMat& k) {
    failure_.clear();
    failed_equation_ = -1;
    {
      // OpenBLAS's threads (set_solver_threads) share only the large supernodes of large systems: on the
      // 1e5-equation tubes two threads factorized no faster, often slower, and left a thread spinning
      // against gapfe's own after every factorization of a Newton run (BENCHMARKS.md "Every core:
      // --threads"). So up to kLargeSystem equations the factor is the same on any number of threads.
      const OneBlasThread small(k.rows() <= kLargeSystem);
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
    const OneBlasThread one(true);
    return llt_.solve(b);
  }
  /// The last analysis' flop count and factor size (cholmod_common fl, lnz) and the values the last
  /// factorization stores (the relaxed supernodes' zeros included).
  FactorStatistics statistics() {
    const cholmod_factor* f = llt_.factor();
    return {llt_.cholmod().fl, llt_.cholmod().lnz, f != nullptr ? static_cast<double>(f->xsize) : 0.0};
  }
  const std::string& failure() const { return failure_; }
  /// After a failed factorize(): the equation (caller's numbering) where L's pivot broke down (CHOLMOD's
  /// `minor`) or, when every pivot was positive but the condition estimate too small, the one with the
  /// smallest pivot: a rigid-body mode's last free DOF in the elimination order. -1 when unknown.
  int failed_equation() const { return failed_equation_; }

 private:
  /// See failed_equation(). Supernode s of L is a dense column-major block of pi[s+1] - pi[s] rows whose
  /// columns super[s]..super[s+1]-1 have their diagonal at px[s] + c (rows + 1), c the column within it
  /// (CHOLMOD's cholmod_factor layout); Perm maps L's columns to the matrix's.
  int weakest_equation() {
    const cholmod_factor* f = llt_.factor();
    if (f == nullptr || f->Perm == nullptr || f->x == nullptr || f->itype != CHOLMOD_INT) return -1;
    const int* perm = static_cast<const int*>(f->Perm);
    if (f->minor < f->n) return perm[f->minor];
    if (!f->is_super) return -1;
    const int *super = static_cast<const int*>(f->super), *pi = static_cast<const int*>(f->pi),
              *px   = static_cast<const int*>(f->px);
    const double* x = static_cast<const double*>(f->x);
    double smallest = INFINITY;
    int worst       = -1;
    for (std::size_t s = 0; s < f->nsuper; ++s) {
      const int rows = pi[s + 1] - pi[s];
      for (int j = super[s]; j < super[s + 1]; ++j)
        if (const double d = std::abs(x[px[s] + static_cast<std::ptrdiff_t>(j - super[s]) * (rows + 1)]);
            d < smallest)
          smallest = d, worst = j;
    }
    return worst >= 0 ? perm[worst] : -1;
  }

  struct Llt : Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> {
    cholmod_factor* factor() { return m_cholmodFactor; }
    /// Eigen's analyzePattern with CHOLMOD_GIVEN: the same state afterwards, the order ours.
    void analyze_in(const SpMat& k, const std::vector<int>& order) {
      if (m_cholmodFactor) cholmod_free_factor(&m_cholmodFactor, &cholmod());
      cholmod_sparse a = Eigen::viewAsCholmod(k.selfadjointView<Eigen::Lower>());
      std::vector<int> perm(order);  // cholmod_analyze_p takes a non-const pointer
      cholmod().method[0].ordering = CHOLMOD_GIVEN;
      m_cholmodFactor              = cholmod_analyze_p(&a, perm.data(), nullptr, 0, &cholmod());
      cholmod().method[0].ordering = CHOLMOD_AMD;
      m_isInitialized              = true;
      m_info                       = m_cholmodFactor ? Eigen::Success : Eigen::InvalidInput;
      m_analysisIsOk               = m_cholmodFactor != nullptr;
      m_factorizationIsOk          = false;
    }
  };
  /// Relaxed amalgamation: CHOLMOD merges a child supernode into its parent when the merged one has at
  /// most nrelax[0] columns (any zeros), nrelax[1] (a zrelax[0] fraction of zeros), nrelax[2] (zrelax[1])
  /// or any size (zrelax[2]). Bigger supernodes mean fewer, larger BLAS calls and fewer of CHOLMOD's
  /// per-supernode passes, paid for with explicit zeros in L. On the tube stiffness with the coordinate
  /// dissection (one thread, BENCHMARKS.md "Levers, each measured") CHOLMOD's defaults {4, 16, 48} factorize
  /// 1e4 equations in 13.8 ms and 1e5 in 185 ms; {16, 64, 256} takes 7.7 ms and 127 ms for 1.5x the factor's
  /// memory, and is the best of the settings tried. Past kLargeSystem equations the factor's memory is what
  /// limits a run, so the moderate {8, 32, 96} (1.1x memory; 1e6 equations 4.0 s instead of 4.7 s) is used
  /// there.
  static constexpr Eigen::Index kLargeSystem = 250000;
  void relax_supernodes(Eigen::Index equations) {
    cholmod_common& c = llt_.cholmod();
    const bool large  = equations > kLargeSystem;
    c.nrelax[0] = large ? 8 : 16, c.nrelax[1] = large ? 32 : 64, c.nrelax[2] = large ? 96 : 256;
    c.zrelax[0] = 0.8, c.zrelax[1] = 0.1, c.zrelax[2] = 0.05;  // CHOLMOD's defaults
  }
  bool fail(const std::string& what) {
    failure_ = what;
    return false;
  }
  Llt llt_;
  std::string failure_;
  int failed_equation_ = -1;
};
static_assert(OrderedSolver<CholmodLlt>);

}  // namespace gapfe

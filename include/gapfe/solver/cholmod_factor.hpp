#pragma once
// The pieces of CHOLMOD (SuiteSparse) that CholmodLlt (solver/cholmod.hpp) and its split into halves
// (solver/split_cholmod.hpp) share: Eigen's supernodal LLT with the factor in reach and the analysis in
// the caller's order, the supernode settings, the walk over a supernodal factor's columns, and the two
// dense LAPACK kernels the split needs. Needs the gapfe::cholmod CMake target (GAPFE_HAS_CHOLMOD).
#include <cstddef>
#include <vector>

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>

#include "gapfe/core/types.hpp"

// LAPACK as OpenBLAS (or any LAPACK CHOLMOD loads) provides it: weak references, as in solver/threads.hpp,
// so nothing more needs linking; Eigen's kernels stand in when no LAPACK is loaded. The trailing length is
// gfortran's hidden argument for the character one.
extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t)
    __attribute__((weak));
void dlauum_(const char* uplo, const int* n, double* a, const int* lda, int* info, std::size_t)
    __attribute__((weak));
}

namespace gapfe::detail {

/// Systems past this many equations are large: their factor's memory is what limits a run.
inline constexpr Eigen::Index kLargeSystem = 250000;

/// Relaxed amalgamation: CHOLMOD merges a child supernode into its parent when the merged one has at
/// most nrelax[0] columns (any zeros), nrelax[1] (a zrelax[0] fraction of zeros), nrelax[2] (zrelax[1])
/// or any size (zrelax[2]). Bigger supernodes mean fewer, larger BLAS calls and fewer of CHOLMOD's
/// per-supernode passes, paid for with explicit zeros in L. On the tube stiffness with the coordinate
/// dissection (one thread, BENCHMARKS.md "Levers, each measured") CHOLMOD's defaults {4, 16, 48} factorize
/// 1e4 equations in 13.8 ms and 1e5 in 185 ms; {16, 64, 256} takes 7.7 ms and 127 ms for 1.5x the factor's
/// memory, and is the best of the settings tried. Past kLargeSystem equations the factor's memory is the
/// run's peak, so CHOLMOD's defaults are kept there: at 1e6 equations, split in halves (split_cholmod.hpp),
/// they store 1.49e8 values against {8, 32, 96}'s 1.63e8 (110 MB less) in about the same time; a large system
/// factorized whole (an order without a top separator) pays about 12% more time for 8% less memory.
/// `equations`: the whole system's.
inline void relax_supernodes(cholmod_common& c, Eigen::Index equations) {
  const bool large = equations > kLargeSystem;
  c.nrelax[0] = large ? 4 : 16, c.nrelax[1] = large ? 16 : 64, c.nrelax[2] = large ? 48 : 256;
  c.zrelax[0] = 0.8, c.zrelax[1] = 0.1, c.zrelax[2] = 0.05;  // CHOLMOD's defaults
}

/// Eigen's CHOLMOD supernodal LLT (lower triangle read), set up as gapfe uses it, with CHOLMOD's factor
/// and an analysis in the caller's elimination order.
struct CholmodFactor : Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> {
  CholmodFactor() {
    cholmod_common& c    = cholmod();
    c.nmethods           = 1;
    c.method[0].ordering = CHOLMOD_AMD;
    c.postorder          = 1;
    c.supernodal         = CHOLMOD_SUPERNODAL;
    c.print              = 0;  // failures are reported by the caller, not printed by CHOLMOD
  }
  cholmod_factor* factor() const { return m_cholmodFactor; }
  /// Eigen's analyzePattern with CHOLMOD_GIVEN: the same state afterwards, the order ours (order[k] = the
  /// equation eliminated k-th).
  void analyze_in(const SpMat& k, const std::vector<int>& order) {
    release();
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
  /// The analysis of k in its own order (no ordering, no postordering; a postorder of k's elimination tree
  /// gives the largest supernodes): L's columns are k's, and CHOLMOD factorizes k's lower triangle where it
  /// lies instead of a permuted copy (cholmod_factorize_p's natural ordering).
  void analyze_natural(const SpMat& k) {
    release();
    cholmod_sparse a             = Eigen::viewAsCholmod(k.selfadjointView<Eigen::Lower>());
    cholmod().method[0].ordering = CHOLMOD_NATURAL;
    cholmod().postorder          = 0;
    m_cholmodFactor              = cholmod_analyze(&a, &cholmod());
    cholmod().method[0].ordering = CHOLMOD_AMD;
    cholmod().postorder          = 1;
    m_isInitialized              = true;
    m_info                       = m_cholmodFactor ? Eigen::Success : Eigen::InvalidInput;
    m_analysisIsOk               = m_cholmodFactor != nullptr;
    m_factorizationIsOk          = false;
  }
  /// The factor freed (a new analysis is needed before the next factorization).
  void release() {
    if (m_cholmodFactor) cholmod_free_factor(&m_cholmodFactor, &cholmod());
    m_analysisIsOk = m_factorizationIsOk = false;
  }
};

/// f(j, rows, values, count) for every column j of a supernodal factor: `count` rows of L's column j (its
/// diagonal first), as row indices and values. Supernode s of L is a dense column-major block of pi[s+1] -
/// pi[s] rows whose columns super[s] .. super[s+1]-1 have their diagonal at px[s] + c (rows + 1), c the
/// column within it (CHOLMOD's cholmod_factor layout).
template <class F>
void for_each_factor_column(const cholmod_factor& f, F&& f_column) {
  const int *super = static_cast<const int*>(f.super), *pi = static_cast<const int*>(f.pi),
            *px = static_cast<const int*>(f.px), *ls = static_cast<const int*>(f.s);
  const double* x = static_cast<const double*>(f.x);
  for (std::size_t s = 0; s < f.nsuper; ++s) {
    const int rows = pi[s + 1] - pi[s];
    for (int j = super[s]; j < super[s + 1]; ++j) {
      const int c = j - super[s];
      f_column(j, ls + pi[s] + c, x + px[s] + static_cast<std::ptrdiff_t>(c) * (rows + 1), rows - c);
    }
  }
}

/// a's lower triangle := its Cholesky factor (LAPACK dpotrf); false when a is not positive definite.
inline bool cholesky_in_place(Eigen::MatrixXd& a) {
  const int n = static_cast<int>(a.rows());
  if (n == 0) return true;
  if (dpotrf_) {
    int info = 0;
    dpotrf_("L", &n, a.data(), &n, &info, 1);
    return info == 0;
  }
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(a);
  return llt.info() == Eigen::Success;
}

/// L L^T of a lower-triangular l (its upper part ignored), reversed: its entry (a, b), a >= b, at (n-1-a,
/// n-1-b) of the upper triangle returned. LAPACK's dlauum forms U U^T of an upper U in place, a sixth of a
/// general product's flops; here U = J l J, J the reversal, and J U U^T J = l l^T.
inline Eigen::MatrixXd reversed_lower_times_transpose(const Eigen::MatrixXd& l) {
  const int n       = static_cast<int>(l.rows());
  Eigen::MatrixXd u = Eigen::MatrixXd::Zero(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = j; i < n; ++i) u(n - 1 - i, n - 1 - j) = l(i, j);
  if (n == 0) return u;
  if (dlauum_) {
    int info = 0;
    dlauum_("U", &n, u.data(), &n, &info, 1);
  } else {
    const Eigen::MatrixXd upper = u.triangularView<Eigen::Upper>();
    u.noalias()                 = upper * upper.transpose();
  }
  return u;
}

}  // namespace gapfe::detail

#pragma once
// How many threads the external solver libraries may use: set_solver_threads(n).
//
// Why this exists: Debian's CHOLMOD (SuiteSparse 5.12) is built with OpenMP and asks for 4 threads in
// parts of its supernodal factorization through a num_threads(4) clause, which OMP_NUM_THREADS does not
// override; OpenBLAS (the pthread build) uses every core for the supernodes' BLAS-3 unless told. On a
// 2-core machine the six threads spin against each other: a 1e4-equation Newton run took 3.1 s with
// OMP_NUM_THREADS=OPENBLAS_NUM_THREADS=1 and 1.6 s with the OpenMP thread limit at 1 (BENCHMARKS.md,
// issue 14). A library must not start threads its caller did not ask for, so callers that link those
// libraries (the `gapfe` command does) call this once before the first factorization.
//
// OpenMP parallel regions always run on the calling thread (max-active-levels 0, which also binds
// num_threads clauses): CHOLMOD's are memory-bound copies and clears. The 1e6-equation tube on 2 cores
// (`gapfe run`, whole process): one thread of each 6.6 s; 2 OpenBLAS threads with OpenMP on one 6.25 s; 2
// of each 10.5 s (BENCHMARKS.md, issue 14). So n goes to OpenBLAS only.
//
// The OpenMP and OpenBLAS entry points are weak references: when the program does not load libgomp or
// OpenBLAS (a header-only build with Eigen's solvers, or another BLAS), the call does nothing for them,
// and nothing needs linking for this header.

extern "C" {
void omp_set_max_active_levels(int) __attribute__((weak));
void omp_set_num_threads(int) __attribute__((weak));
void openblas_set_num_threads(int) __attribute__((weak));
}

namespace gapfe {

/// From now on: OpenMP (CHOLMOD) on the calling thread, OpenBLAS on n >= 1 threads. Returns true when at
/// least one of the two runtimes is loaded (and so was told).
inline bool set_solver_threads(int n) {
  if (n < 1) n = 1;
  bool told = false;
  if (omp_set_max_active_levels && omp_set_num_threads) {
    omp_set_max_active_levels(0);
    omp_set_num_threads(1);
    told = true;
  }
  if (openblas_set_num_threads) {
    openblas_set_num_threads(n);
    told = true;
  }
  return told;
}

}  // namespace gapfe

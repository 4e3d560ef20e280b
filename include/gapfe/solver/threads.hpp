#pragma once
// How many threads the external solver libraries may use: set_solver_threads(n).
//
// Why this exists: Debian's CHOLMOD (SuiteSparse 5.12) is built with OpenMP and asks for 4 threads in
// parts of its supernodal factorization through a num_threads(4) clause, which OMP_NUM_THREADS does not
// override; OpenBLAS (the pthread build) uses every core for the supernodes' BLAS-3 unless told. On a
// 2-core machine the six threads spin against each other: a 1e4-equation Newton run took 3.1 s with
// OMP_NUM_THREADS=OPENBLAS_NUM_THREADS=1 and 1.6 s with the OpenMP thread limit at 1 (BENCHMARKS.md,
// "Levers, each measured"). A library must not start threads its caller did not ask for, so callers that link
// those libraries (the `gapfe` command does) call this once before the first factorization.
//
// OpenMP parallel regions always run on the calling thread (max-active-levels 0, which also binds
// num_threads clauses): CHOLMOD's are memory-bound copies and clears. The 1e6-equation tube on 2 cores
// (`gapfe run`, whole process): one thread of each 6.6 s; 2 OpenBLAS threads with OpenMP on one 6.25 s; 2
// of each 10.5 s (BENCHMARKS.md, "Levers, each measured"). So n goes to OpenBLAS only.
//
// An OpenBLAS built with OpenMP (Debian's libopenblas0-openmp) runs its threads as OpenMP regions, which
// the limit above keeps on one thread; so does the `gapfe` program's interposed OpenMP entry point
// (docs/process.md). More threads are then not to be had: set_solver_threads gives 1 and says why.
//
// The OpenMP and OpenBLAS entry points are weak references: when the program does not load libgomp or
// OpenBLAS (a header-only build with Eigen's solvers, or another BLAS), the call does nothing for them,
// and nothing needs linking for this header.

#include <string>

extern "C" {
void omp_set_max_active_levels(int) __attribute__((weak));
void omp_set_num_threads(int) __attribute__((weak));
void openblas_set_num_threads(int) __attribute__((weak));
int openblas_get_num_threads() __attribute__((weak));
int openblas_get_parallel() __attribute__((weak));  // 0 sequential, 1 pthreads, 2 OpenMP
}

namespace gapfe {

/// The threads the solver libraries were given: how many, and why fewer than asked (empty when not).
struct SolverThreads {
  int threads = 1;
  std::string limited;
};

/// OpenMP regions that this thread starts run on it alone (CHOLMOD's memory-bound copies, see the top).
/// libgomp keeps these settings per thread, so every thread that calls CHOLMOD makes them: set_solver_threads
/// for the calling one, SplitCholmod for the pool's workers (two halves' factorizations with OpenMP teams of
/// four each ran no faster than one after the other on 2 cores).
inline void openmp_inline_on_this_thread() {
  if (omp_set_max_active_levels && omp_set_num_threads) {
    omp_set_max_active_levels(0);
    omp_set_num_threads(1);
  }
}

/// From now on: OpenMP (CHOLMOD) on the calling thread, OpenBLAS on n >= 1 threads, unless OpenBLAS itself
/// threads with OpenMP: then on one, and `limited` says so.
inline SolverThreads set_solver_threads(int n) {
  SolverThreads given{n < 1 ? 1 : n, {}};
  if (given.threads > 1 && openblas_get_parallel && openblas_get_parallel() == 2) {
    given.limited =
        "--threads " + std::to_string(given.threads) +
        ": this process's OpenBLAS threads with OpenMP, which gapfe keeps on one thread (CHOLMOD's "
        "fixed 4-thread regions would oversubscribe the cores); the factorization's dense kernels run on "
        "1 thread. The pthread build (libopenblas0-pthread, Debian's default) takes --threads";
    given.threads = 1;
  }
  openmp_inline_on_this_thread();
  if (openblas_set_num_threads) openblas_set_num_threads(given.threads);
  return given;
}

/// OpenBLAS on one thread while this lives, when `active` (and back to its count after): for BLAS work
/// whose blocks are too small to share between threads (CholmodLlt::factorize on small systems, its
/// solves), and for SplitCholmod's halves, whose factor is then the same on any number of threads. Nothing is
/// set when OpenBLAS already runs on one (set_solver_threads with an OpenMP-built OpenBLAS, whose set call
/// would also set OpenMP's).
class OneBlasThread {
 public:
  explicit OneBlasThread(bool active) {
    if (!active || !openblas_get_num_threads || !openblas_set_num_threads) return;
    before_ = openblas_get_num_threads();
    if (before_ > 1) openblas_set_num_threads(1);
  }
  OneBlasThread(const OneBlasThread&)            = delete;
  OneBlasThread& operator=(const OneBlasThread&) = delete;
  ~OneBlasThread() {
    if (before_ > 1) openblas_set_num_threads(before_);
  }

 private:
  int before_ = 0;
};

}  // namespace gapfe

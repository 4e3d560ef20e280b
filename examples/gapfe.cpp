// main() of the `gapfe` command (gapfe_cli.cpp does the work). A progress line is drawn only when
// standard error is a terminal.
#include <cstdlib>
#include <iostream>
#include <malloc.h>
#include <string>
#include <unistd.h>

#include "gapfe_cli.hpp"

// OpenMP parallel regions run inline. The command keeps every OpenMP region on the calling thread
// (gapfe/solver/threads.hpp: CHOLMOD's regions are memory-bound copies and clears, and OpenBLAS gets the
// threads), yet libgomp still builds a team for each region and ends it with a futex wake-up system call.
// CHOLMOD's supernodal factorization opens a few regions per supernode: 1,540 per factorization of the
// 1e4-equation plastic tube, 41,554 system calls in its 27 factorizations, 10-15% of the run on the virtual
// machines we measure on (BENCHMARKS.md, issue 14, lever 13). Defining GCC's entry point for
// `#pragma omp parallel` (libgomp's ABI since GCC 4.9) in the executable interposes it for the shared
// libraries: the outlined body runs once on this thread, outside any team, where omp_get_num_threads()
// is 1 and omp_get_thread_num() is 0, so a `parallel for` covers its whole range, as a one-thread team
// would. Only this program does this; the library never defines OpenMP symbols.
extern "C" {
__attribute__((visibility("default"))) void GOMP_parallel(void (*body)(void*), void* data, unsigned threads,
                                                          unsigned flags);
void GOMP_parallel(void (*body)(void*), void* data, unsigned /*threads*/, unsigned /*flags*/) {
  body(data);
}
}

namespace {

/// Freed blocks stay with malloc. A Newton or contact run allocates and frees the same large blocks
/// every iteration (CHOLMOD's permuted copy of the matrix and its supernodal workspace, the residual's
/// scratch); glibc maps blocks above a sliding threshold (at most 32 MiB) afresh and trims the heap's
/// top above twice that, so each iteration paid its page faults again. Fixing both thresholds high
/// keeps that memory in the process: peak memory of the 1e6-equation tube +1%, the plastic and contact
/// runs 5-10% faster (BENCHMARKS.md, issue 14, lever 13).
void keep_freed_memory() {
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

/// Transparent huge pages for malloc's large blocks. A large run touches hundreds of megabytes for the
/// first time (the stiffness, its factor, the output buffers), one page fault per 4 KiB page; on the
/// virtual machines we measure on a fault costs microseconds, and on the 1e5-equation tube the faults
/// were a third of the wall time (BENCHMARKS.md, issue 14). glibc (2.35 and later) advises the kernel
/// to back its large blocks with huge pages when the tunable glibc.malloc.hugetlb=1 is set, and reads
/// tunables only at start-up, so the command re-executes itself once with it added to GLIBC_TUNABLES,
/// when the deck it has just read is large (gapfe::cli::kLargeModel grid points; below that the exec's
/// start-up, 13 ms with OpenBLAS and SuiteSparse to load, costs more than the faults). Nothing changes
/// when the kernel has transparent huge pages off; GAPFE_HUGE_PAGES=0 skips this, and a failed exec just
/// goes on without.
void use_huge_pages(char** argv) {
  if (const char* off = std::getenv("GAPFE_HUGE_PAGES"); off && std::string(off) == "0") return;
  const char* set          = std::getenv("GLIBC_TUNABLES");
  const std::string before = set ? set : "";
  if (before.find("glibc.malloc.hugetlb") != std::string::npos) return;  // the user's, or the exec's
  const std::string tunables = before + (before.empty() ? "" : ":") + "glibc.malloc.hugetlb=1";
  if (setenv("GLIBC_TUNABLES", tunables.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  if (before.empty())  // the exec failed: leave the environment as it was
    unsetenv("GLIBC_TUNABLES");
  else
    setenv("GLIBC_TUNABLES", before.c_str(), 1);
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory();
  std::vector<std::string> args(argv + 1, argv + argc);
  return gapfe::cli::main(args, std::cout, std::cerr, isatty(STDERR_FILENO) != 0,
                          [argv] { use_huge_pages(argv); });
}

#pragma once
// What the `gapfe` program does to its own process, in one place (docs/process.md gives each one's
// measured gain). Each is a property of the process, not of the library: a program of one's own that
// includes the headers gets none of them, and each has a switch in the environment that turns it off:
//
//   GAPFE_OPENMP_INLINE=0  OpenMP parallel regions get their teams again (openmp_teams, GOMP_parallel below)
//   GAPFE_KEEP_MEMORY=0    malloc keeps glibc's default thresholds (keep_freed_memory)
//   GAPFE_HUGE_PAGES=0     no re-execution with huge pages for large models (use_huge_pages)
//   GAPFE_RANK_LISTENER=0  an MPI launch without its listening thread (mpi_launch.hpp)
//
// Only the program defines OpenMP symbols; the library never does. Included once, by main.cpp.
#include <cstdlib>
#include <dlfcn.h>
#include <malloc.h>
#include <string>
#include <unistd.h>

namespace program {

/// Whether the environment switch `name` is off ("0"); every switch is on when unset.
inline bool switched_off(const char* name) {
  const char* value = std::getenv(name);
  return value && std::string(value) == "0";
}

/// Freed blocks stay with malloc. A Newton or contact run allocates and frees the same large blocks every
/// iteration (CHOLMOD's permuted copy of the matrix and its supernodal workspace, the residual's scratch);
/// glibc maps blocks above a sliding threshold (at most 32 MiB) afresh and trims the heap's top above twice
/// that, so each iteration paid its page faults again. Fixing both thresholds high keeps that memory in the
/// process, at about 1% more peak memory on the 1e6-equation tube.
inline void keep_freed_memory() {
  if (switched_off("GAPFE_KEEP_MEMORY")) return;
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

/// Transparent huge pages for malloc's large blocks. A large run touches hundreds of megabytes for the
/// first time (the stiffness, its factor, the output buffers), one page fault per 4 KiB page, and a fault
/// costs microseconds on a virtual machine. glibc (2.35 and later) backs its large blocks with huge pages
/// when the tunable glibc.malloc.hugetlb=1 is set, and reads tunables only at start-up, so the program
/// re-executes itself once with it added to GLIBC_TUNABLES when the model it has just read is large
/// (gapfe::app::kLargeModel; below that the exec's start-up, 13 ms with OpenBLAS and SuiteSparse to load,
/// costs more than the faults). Nothing changes when the kernel has transparent huge pages off, and a
/// failed exec just goes on without.
inline void use_huge_pages(char** argv) {
  if (switched_off("GAPFE_HUGE_PAGES")) return;
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

/// libgomp's entry point for `#pragma omp parallel` (its ABI since GCC 4.9).
using OpenMpParallel = void (*)(void (*body)(void*), void* data, unsigned threads, unsigned flags);

/// libgomp's own GOMP_parallel when GAPFE_OPENMP_INLINE=0, else nullptr: regions run inline.
inline OpenMpParallel openmp_teams() {
  static const OpenMpParallel real = [] {
    if (!switched_off("GAPFE_OPENMP_INLINE")) return OpenMpParallel{};
    return reinterpret_cast<OpenMpParallel>(dlsym(RTLD_NEXT, "GOMP_parallel"));
  }();
  return real;
}

}  // namespace program

// OpenMP parallel regions run inline: those that enter libgomp through GOMP_parallel, as `#pragma omp
// parallel` and CHOLMOD's do (GOMP_parallel_loop_* and GOMP_parallel_sections keep their teams). The command
// keeps every OpenMP region on the calling thread
// (gapfe/solver/threads.hpp: CHOLMOD's regions are memory-bound copies and clears, and OpenBLAS gets the
// threads; an OpenMP-built BLAS is held to one thread, with a warning), yet libgomp still builds a team for
// each region and ends it with a futex wake-up system call. CHOLMOD's supernodal factorization opens a few
// regions per supernode: 1,540 per factorization of the 1e4-equation plastic tube, 41,554 system calls in
// its 27 factorizations. Defining GCC's entry point in the executable interposes it for the shared
// libraries: the outlined body runs once on this thread, outside any team, where omp_get_num_threads() is
// 1 and omp_get_thread_num() is 0, so a `parallel for` covers its whole range, as a one-thread team would.
extern "C" {
__attribute__((visibility("default"))) void GOMP_parallel(void (*body)(void*), void* data, unsigned threads,
                                                          unsigned flags);
void GOMP_parallel(void (*body)(void*), void* data, unsigned threads, unsigned flags) {
  if (const program::OpenMpParallel teams = program::openmp_teams())
    teams(body, data, threads, flags);
  else
    body(data);
}
}

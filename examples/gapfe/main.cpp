// main() of the `gapfe` command: the process set-up (memory, huge pages, OpenMP, MPI and PETSc) around one
// library call, gapfe::app::command (include/gapfe/app/command.hpp), which does the work. A progress line
// is drawn only when standard error is a terminal.
#include <cstdlib>
#include <iostream>
#include <malloc.h>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "gapfe/app/command.hpp"
#ifdef GAPFE_HAS_PETSC
#include <chrono>
#include <cstdio>
#include <petscsys.h>
#include <thread>
#endif

// OpenMP parallel regions run inline. The command keeps every OpenMP region on the calling thread
// (gapfe/solver/threads.hpp: CHOLMOD's regions are memory-bound copies and clears, and OpenBLAS gets the
// threads), yet libgomp still builds a team for each region and ends it with a futex wake-up system call.
// CHOLMOD's supernodal factorization opens a few regions per supernode: 1,540 per factorization of the
// 1e4-equation plastic tube, 41,554 system calls in its 27 factorizations, 10-15% of the run on the virtual
// machines we measure on (BENCHMARKS.md, "Levers measured on the second machine", lever 13). Defining GCC's
// entry point for
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
/// runs 5-10% faster (BENCHMARKS.md, "Levers measured on the second machine", lever 13).
void keep_freed_memory() {
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

/// Transparent huge pages for malloc's large blocks. A large run touches hundreds of megabytes for the
/// first time (the stiffness, its factor, the output buffers), one page fault per 4 KiB page; on the
/// virtual machines we measure on a fault costs microseconds, and on the 1e5-equation tube the faults
/// were a third of the wall time (BENCHMARKS.md, "Levers measured on the second machine", lever 5). glibc
/// (2.35 and later) advises the kernel to back its large blocks with huge pages when the tunable
/// glibc.malloc.hugetlb=1 is set, and reads tunables only at start-up, so the command re-executes itself once
/// with it added to GLIBC_TUNABLES, when the deck it has just read is large (gapfe::app::kLargeModel grid
/// points; below that the exec's start-up, 13 ms with OpenBLAS and SuiteSparse to load, costs more than the
/// faults). Nothing changes when the kernel has transparent huge pages off; GAPFE_HUGE_PAGES=0 skips this,
/// and a failed exec just goes on without.
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

#ifdef GAPFE_HAS_PETSC
/// MPI and PETSc for a partitioned run (solver = petsc), owned by the program: started on the command's
/// request with PETSc's options from the command line, ended once the run is over.
class Mpi {
 public:
  // -skip_petscrc: PETSc's options come from the command line and PETSC_OPTIONS only, never from a
  // petscrc in the working or home folder (running in someone else's case folder would adopt its
  // options: a solver, or -log_view :FILE writing over FILE); -options_file FILE still names one.
  explicit Mpi(const char* program) : words_{program, "-skip_petscrc"} {}

  std::pair<int, int> start(const std::vector<std::string>& options) {
    if (!started_) {
      words_.insert(words_.end(), options.begin(), options.end());
      for (auto& w : words_) pointers_.push_back(w.data());
      pointers_.push_back(nullptr);
      int argc    = static_cast<int>(words_.size());
      char** argv = pointers_.data();
      if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0)
        throw std::runtime_error("PetscInitialize failed");
      started_ = true;
      MPI_Comm_dup(PETSC_COMM_WORLD, &check_);  // the exit codes' own channel (finish())
      MPI_Comm_rank(PETSC_COMM_WORLD, &rank_);
      MPI_Comm_size(PETSC_COMM_WORLD, &size_);
    }
    return {rank_, size_};
  }

  /// The worst exit code of all ranks, then PETSc and MPI end. The ranks read, check and decide alike, so
  /// a failure is everyone's and they all get here; a rank that failed alone would leave the others in a
  /// collective call, so a failed rank waits for the others at most two minutes and then aborts the launch
  /// (a rank that succeeded waits as long as rank 0 writes).
  int finish(int code) {
    if (!started_) return code;
    int worst           = code;
    MPI_Request request = MPI_REQUEST_NULL;
    MPI_Iallreduce(&code, &worst, 1, MPI_INT, MPI_MAX, check_, &request);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
    for (int done = 0;;) {
      MPI_Test(&request, &done, MPI_STATUS_IGNORE);
      if (done) break;
      if (code != 0 && std::chrono::steady_clock::now() > deadline) {
        std::fprintf(
            stderr, "gapfe: rank %d failed and the other ranks did not finish: aborting the launch\n", rank_);
        MPI_Abort(PETSC_COMM_WORLD, code);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    MPI_Comm_free(&check_);
    PetscFinalize();
    return worst;
  }

 private:
  std::vector<std::string> words_;
  std::vector<char*> pointers_;
  bool started_ = false;
  int rank_ = 0, size_ = 1;
  MPI_Comm check_ = MPI_COMM_NULL;
};
#endif

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory();
  std::vector<std::string> args(argv + 1, argv + argc);
  gapfe::app::Process process;
  process.progress    = isatty(STDERR_FILENO) != 0;
  process.large_model = [argv] { use_huge_pages(argv); };
#ifdef GAPFE_HAS_PETSC
  Mpi mpi(argv[0]);
  process.start_mpi = [&](const std::vector<std::string>& options) { return mpi.start(options); };
  const int code    = gapfe::app::command(args, std::cout, std::cerr, process);
  std::cout.flush();
  return mpi.finish(code);
#else
  return gapfe::app::command(args, std::cout, std::cerr, process);
#endif
}

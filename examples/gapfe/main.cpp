// main() of the `gapfe` command: the process set-up (memory, huge pages, OpenMP: process.hpp and
// docs/process.md; MPI and PETSc) around one library call, gapfe::app::command
// (include/gapfe/app/command.hpp), which does the work. A progress line is drawn only when standard error is
// a terminal.
#include <iostream>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "gapfe/app/command.hpp"

#include "process.hpp"
#ifdef GAPFE_HAS_PETSC
#include <chrono>
#include <cstdio>
#include <petscsys.h>
#include <thread>
#endif

namespace {

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
  program::keep_freed_memory();
  std::vector<std::string> args(argv + 1, argv + argc);
  gapfe::app::Process process;
  process.progress    = isatty(STDERR_FILENO) != 0;
  process.large_model = [argv] { program::use_huge_pages(argv); };
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

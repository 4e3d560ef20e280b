// main() of the `gapfe` command: the process set-up (memory, huge pages, OpenMP: process.hpp and
// docs/process.md; MPI and PETSc) around one library call, gapfe::app::command
// (include/gapfe/app/command.hpp), which does the work. A progress line is drawn only when standard error is
// a terminal.
#include <functional>
#include <iostream>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

#include "gapfe/app/command.hpp"

#include "process.hpp"
#ifdef GAPFE_HAS_PETSC
#include "mpi_launch.hpp"
#endif

int main(int argc, char** argv) {
  program::keep_freed_memory();
  std::vector<std::string> args(argv + 1, argv + argc);
  gapfe::app::Process process;
  process.progress = isatty(STDERR_FILENO) != 0;
#ifdef GAPFE_HAS_PETSC
  // A launch of several processes starts MPI before it reads the deck (app/launch.hpp), and a process
  // cannot re-execute itself once MPI has started: it takes its huge pages at the start instead.
  const int launch_size = gapfe::app::launcher_ranks().second;
  if (launch_size > 1) program::use_huge_pages(argv);
  program::Launch launch(argv[0], launch_size, !program::switched_off("GAPFE_RANK_LISTENER"));
  process.large_model = [&launch, argv] {
    if (!launch.mpi_up()) program::use_huge_pages(argv);
  };
  process.start_mpi = [&](const std::vector<std::string>& options) { return launch.start(options); };
  process.failing   = [&] { launch.failing(); };
  process.failed    = [&](int code, const std::string& line) { launch.failed(code, line); };
  process.on_ended  = [&](std::function<void(const std::string&)> record) {
    launch.on_ended(std::move(record));
  };
  const int code = gapfe::app::command(args, std::cout, std::cerr, process);
  std::cout.flush();
  return launch.finish(code);
#else
  process.large_model = [argv] { program::use_huge_pages(argv); };
  return gapfe::app::command(args, std::cout, std::cerr, process);
#endif
}

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
  process.progress    = isatty(STDERR_FILENO) != 0;
  process.large_model = [argv] { program::use_huge_pages(argv); };
#ifdef GAPFE_HAS_PETSC
  program::Launch launch(argv[0], gapfe::app::launcher_ranks().second);
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
  return gapfe::app::command(args, std::cout, std::cerr, process);
#endif
}

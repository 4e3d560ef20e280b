// main() of the `gapfe` command (gapfe_cli.cpp does the work). A progress line is drawn only when
// standard error is a terminal.
#include <cstdlib>
#include <iostream>
#include <string>
#include <unistd.h>

#include "gapfe_cli.hpp"

namespace {

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
  std::vector<std::string> args(argv + 1, argv + argc);
  return gapfe::cli::main(args, std::cout, std::cerr, isatty(STDERR_FILENO) != 0,
                          [argv] { use_huge_pages(argv); });
}

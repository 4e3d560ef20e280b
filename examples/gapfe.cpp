// main() of the `gapfe` command (gapfe_cli.cpp does the work). A progress line is drawn only when
// standard error is a terminal.
#include <iostream>
#include <unistd.h>

#include "gapfe_cli.hpp"

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  return gapfe::cli::main(args, std::cout, std::cerr, isatty(STDERR_FILENO) != 0);
}

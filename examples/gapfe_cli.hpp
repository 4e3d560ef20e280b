#pragma once
// The `gapfe` command as a function, so that the tests can run it (and check its exit codes and
// messages) in-process; gapfe.cpp is its main(). See README.md ("Running decks").
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace gapfe::cli {

/// Exit codes: 0 success; 1 the deck or the model is wrong (InputError); 2 the system cannot be
/// solved (SolveError); 3 a file cannot be read or written, or memory ran out; 64 bad command line.
enum Exit : int { ok = 0, input = 1, solve = 2, system = 3, usage = 64 };

/// Index-grid points (MAXI x MAXJ) times load steps from which a `run` or `mesh` calls main()'s
/// `large_model`, once the deck is read and before the mesh is built: gapfe.cpp re-executes itself
/// there with huge pages, which pay for their 13 ms start-up when a run touches hundreds of MB, or tens
/// of MB again and again in Newton and contact iterations (BENCHMARKS.md, issue 14, levers 9 and 13).
inline constexpr long kLargeModel = 20000;

/// `args` excludes the program name. Normal output goes to `out`, errors and progress to `err`;
/// `progress` draws a step counter on `err` (gapfe.cpp turns it on when stderr is a terminal).
int main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, bool progress = false,
         const std::function<void()>& large_model = {});

}  // namespace gapfe::cli

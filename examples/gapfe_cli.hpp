#pragma once
// The `gapfe` command as a function, so that the tests can run it (and check its exit codes and
// messages) in-process; gapfe.cpp is its main(). See README.md ("Running decks").
#include <functional>
#include <iosfwd>
#include <string>
#include <utility>
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

/// A partitioned run (solver = petsc) needs MPI and PETSc, which the program starts and ends, never the
/// library: `start_mpi(petsc_options)` initializes PETSc once with PETSc's options from the command line
/// (-ksp_type cg ...) and returns this process's rank and the number of ranks. gapfe.cpp gives it when built
/// with PETSc (GAPFE_WITH_PETSC); without it, solver = petsc is refused.
using StartMpi = std::function<std::pair<int, int>(const std::vector<std::string>& petsc_options)>;

/// This process's rank and the number of processes as an MPI launcher (mpirun, srun) announces them in the
/// environment before MPI starts; (0, 1) without one. Before a partitioned run starts MPI, only rank 0 of a
/// launch speaks, and a launch of several processes without solver = petsc is refused.
std::pair<int, int> launcher_ranks();

/// `args` excludes the program name. Normal output goes to `out`, errors and progress to `err`;
/// `progress` draws a step counter on `err` (gapfe.cpp turns it on when stderr is a terminal).
int main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, bool progress = false,
         const std::function<void()>& large_model = {}, const StartMpi& start_mpi = {});

}  // namespace gapfe::cli

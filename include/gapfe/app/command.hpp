#pragma once
// The `gapfe` command as one library call (a program over a library, as Gmsh's app over its API). command()
// parses the arguments, reads the deck or scene, makes the plan, runs it and reports, and maps the outcome to
// an exit code; the program (examples/gapfe/main.cpp) only sets up the process around it. Declared here,
// defined in app/command_impl.hpp, which one translation unit includes (the gapfe::app target's,
// cmake/app.cmake), so that the tests run the command in-process. docs/decks.md "Running decks".
#include <functional>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace gapfe::app {

/// Exit codes: 0 success; 1 the deck or the model is wrong (InputError); 2 the system cannot be
/// solved (SolveError); 3 a file cannot be read or written, or memory ran out; 64 bad command line.
enum Exit : int { ok = 0, input = 1, solve = 2, system = 3, usage = 64 };

/// Index-grid points (MAXI x MAXJ) times load steps from which a `run` or `mesh` calls the process's
/// `large_model`, once the deck is read and before the mesh is built: the program re-executes itself there
/// with huge pages, which pay for their 13 ms start-up when a run touches hundreds of MB, or tens of MB
/// again and again in Newton and contact iterations (BENCHMARKS.md, "Levers measured on the second machine",
/// lever 5).
inline constexpr long kLargeModel = 20000;

/// A partitioned run (solver = petsc) needs MPI and PETSc, which the program starts and ends, never the
/// library: `start_mpi(petsc_options)` initializes PETSc once with PETSc's options from the command line
/// (-ksp_type cg ...) and returns this process's rank and the number of ranks. Without it, solver = petsc is
/// refused.
using StartMpi = std::function<std::pair<int, int>(const std::vector<std::string>& petsc_options)>;

/// What the program gives the command about its process.
struct Process {
  bool progress = false;              ///< draw a step counter on the error stream (a terminal)
  std::function<void()> large_model;  ///< called for large models (kLargeModel); may not return
  StartMpi start_mpi;                 ///< starts MPI and PETSc for solver = petsc
  /// A run on this rank has failed and is closing its files (rank 0 of a partitioned run writes them): it
  /// no longer waits for the other ranks (docs/cluster.md "When a rank fails").
  std::function<void()> failing;
  /// The command has failed with this exit code and this one-line message, which rank 0 prints: called
  /// on every rank of a launch, so that a rank that failed alone can say why.
  std::function<void(int code, const std::string& line)> failed;
  /// The command hands the program what to record in the run's folder should the program end the launch
  /// from outside this rank's work (another rank failed alone: examples/gapfe/mpi_launch.hpp), and withdraws
  /// it (an empty function) once the run is over.
  std::function<void(std::function<void(const std::string& why)>)> on_ended;
};

/// This process's rank and the number of processes as an MPI launcher (mpirun, srun) announces them in the
/// environment before MPI starts; (0, 1) without one. Before a partitioned run starts MPI, only rank 0 of a
/// launch speaks, and a launch of several processes without solver = petsc is refused.
std::pair<int, int> launcher_ranks();

/// The command: `args` excludes the program name. Normal output goes to `out`, errors and progress to
/// `err`. Returns an Exit code.
int command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
            const Process& process = {});

}  // namespace gapfe::app

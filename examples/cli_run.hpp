#pragma once
// What the `gapfe run` command's run code shares: the request, the timings it reports, the solver
// policy every compiled model uses, and the write of one increment. Internal to the command.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "gapfe/contact/pair_state.hpp"
#include "gapfe/element/legacy_quad.hpp"
#include "gapfe/element/quad4.hpp"
#include "gapfe/io/deck.hpp"
#include "gapfe/io/deck_output.hpp"
#include "gapfe/io/deck_scene.hpp"
#include "gapfe/kinematics/axisym2.hpp"
#include "gapfe/kinematics/axisym3.hpp"
#include "gapfe/solver/eigen_ldlt.hpp"
#include "gapfe/solver/eigen_lu.hpp"
#include "gapfe/solver/runtime_solver.hpp"
#ifdef GAPFE_HAS_CHOLMOD
#include "gapfe/solver/cholmod.hpp"
#endif
#ifdef GAPFE_HAS_UMFPACK
#include "gapfe/solver/umfpack.hpp"
#endif
#ifdef GAPFE_HAS_PETSC
#include "gapfe/solver/petsc.hpp"
#endif
#include "gapfe/post/gather.hpp"
#include "gapfe/run/deck_run.hpp"

namespace gapfe::cli {

/// Wall-clock seconds of a run's phases after meshing, and the work of contact and plasticity.
struct RunTimes {
  double assemble = 0, factorize = 0, solve = 0, write = 0;
  ContactCounters contact;
  int increments = 0, closed = 0, pairs = 0;
  double penalty        = 0;
  int newton_iterations = 0, cut_steps = 0, plastic_points = 0, factorizations = 0;
  int element_passes = 0, tangents = 0;  ///< Newton's F_int evaluations, and those that assembled K_t
  int stalled  = 0;  ///< increments accepted at round-off (NewtonOptions::stall_factor), not the tolerance
  double drift = 0, worst_residual = 0;
  double time_error =
      0;  ///< rate-dependent laws: the largest StepReport::time_error of an accepted increment
  /// Linear laws: the largest |K u - f| / |f| over the free DOFs of an accepted increment's solve (issue 15:
  /// ill-conditioning shows here, as round-off the factorization could not hold), and its load step.
  double equilibrium   = 0;
  int equilibrium_step = 0;
  /// Per load step (index step - 1), the largest relative residual of its accepted increments: a linear
  /// law's |K u - f| / |f|, Newton's |R| / |F_int| for a law with history (both relative to the loads too,
  /// docs/checks.md; the log prints them).
  std::vector<double> step_residual;
  /// Global equilibrium (Solution::balance): per load step its accepted increments' largest
  /// Balance::relative(), the largest of the run with its step, and the last increment's balance.
  std::vector<double> step_balance;
  double balance   = 0;
  int balance_step = 0;
  Balance last_balance;
  /// Runs with friction: per load step (index step - 1), the largest |f_t| / (mu f_n) of a closed pair
  /// (ConeExcess), and where over the run it was largest (the log and the warning past Coulomb's cone).
  std::vector<double> step_cone;
  struct ConeWorst {
    double ratio = 0, inc = 0, normal_force = 0;
    int step = 0, element = -1, pair = -1, node_a = -1, node_b = -1;  ///< 0-based element and nodes
    bool slipping = false;                                            ///< the pair's status at that increment
    bool outline  = false;  ///< a node of the pair lies on the mesh's outline (an end of the fit)
  } cone;
  /// Rate-dependent laws: per accepted increment, lambda dt over the yielding points (the log prints it).
  std::vector<std::string> relaxation;
  /// The pictures StepFiles drew at the end (paths), and why any asked for were not.
  std::vector<std::string> pictures;
  std::string pictures_skipped;
};

/// What a run needs: the deck, its scene, where to write, and the resolved variant choices.
struct RunRequest {
  const Deck& deck;
  const DeckScene& scene;
  std::string dir;
  std::string variant;  ///< saas | saga
  std::string element;  ///< legacy | quad4 | quad4bbar (resolved, never auto)
  std::string solver;   ///< eigen | cholmod (resolved)
  std::ostream& err;
  bool progress;
  std::vector<std::string> pictures;  ///< fields drawn for the last increment (StepFiles::draw_fields)
  PlotUnits units;
  /// A partitioned run (solver = petsc): this process's part of the scene; nullptr: the whole scene here.
  const DeckPart* part = nullptr;
  /// Whether this process writes the files (rank 0 of a partitioned run, which gathers the results).
  bool writes = true;
};

/// Run the request on the compiled variant that matches it (cli_variants.hpp); InputError when the
/// deck asks for a combination the command does not offer (with the reason).
void run_deck_request(const RunRequest& r, RunTimes& times);  // cli_run.cpp

/// The deck option value (element = ...) of each element type.
template <class E>
struct CliName;
template <>
struct CliName<LegacyQuad> {
  static constexpr const char* value = "legacy";
};
template <>
struct CliName<Quad4> {
  static constexpr const char* value = "quad4";
};
template <>
struct CliName<Quad4BBar> {
  static constexpr const char* value = "quad4bbar";
};

/// The command's solver: EigenLdlt, CHOLMOD or PETSc, chosen per run (one instantiation of every model).
/// The solver of the Coulomb rows: the slip tangent is unsymmetric, so an LU on full storage: UMFPACK
/// when SuiteSparse has it (solver = auto | cholmod), else Eigen's SparseLU (and solver = eigen); MUMPS'
/// LU through PETSc with solver = petsc.
#if defined(GAPFE_HAS_CHOLMOD) && defined(GAPFE_HAS_PETSC)
using CliSolver = RuntimeSolver<EigenLdlt, CholmodLlt, PetscSolver<>>;
#elif defined(GAPFE_HAS_CHOLMOD)
using CliSolver   = RuntimeSolver<EigenLdlt, CholmodLlt>;
#elif defined(GAPFE_HAS_PETSC)
using CliSolver   = RuntimeSolver<EigenLdlt, PetscSolver<>>;
#else
using CliSolver   = RuntimeSolver<EigenLdlt>;
#endif
#if defined(GAPFE_HAS_UMFPACK) && defined(GAPFE_HAS_PETSC)
using CliLuSolver = RuntimeSolver<EigenLu, UmfpackLu, PetscSolver<MatrixStorage::full>>;
#elif defined(GAPFE_HAS_UMFPACK)
using CliLuSolver = RuntimeSolver<EigenLu, UmfpackLu>;
#elif defined(GAPFE_HAS_PETSC)
using CliLuSolver = RuntimeSolver<EigenLu, PetscSolver<MatrixStorage::full>>;
#else
using CliLuSolver = RuntimeSolver<EigenLu>;
#endif

/// The log's progress line.
inline void progress_line(const RunRequest& r, int step) {
  if (r.progress) r.err << "\rstep " << step << "/" << r.deck.steps() << std::flush;
}
inline void progress_done(const RunRequest& r) {
  if (r.progress) r.err << "\r" << std::string(32, ' ') << "\r" << std::flush;
}

/// The result files of a run: on the process that writes them (every process of a whole run; rank 0 of a
/// partitioned one), empty elsewhere.
using RunFiles = std::optional<StepFiles>;

/// `per_step[step - 1]` becomes the largest of it and `value` (a figure per load step: its worst increment).
inline void keep_largest(std::vector<double>& per_step, int step, double value) {
  if (per_step.size() < static_cast<std::size_t>(step)) per_step.resize(static_cast<std::size_t>(step), 0.0);
  double& worst = per_step[static_cast<std::size_t>(step - 1)];
  worst         = std::max(worst, value);
}

/// One accepted increment: refuse a non-finite solution, write the files (timed; a partitioned run gathers
/// the whole mesh's results to the writing rank first), show progress.
template <class Fe>
void write_increment(const RunRequest& r, RunTimes& times, RunFiles& files, int step, double inc,
                     const Fe& fe, std::vector<VtuField> extra_cells = {},
                     const IncrementSummary& summary = {}) {
  const Solution& solution = fe.solution();
  if (!std::isfinite(solution.residual) || !solution.displacement.allFinite() ||
      !solution.reaction.allFinite() || !std::isfinite(solution.balance.relative()))
    throw SolveError("load step " + std::to_string(step) + ": the solution is not finite");
  // A law with history reports Newton's out-of-balance here instead (the tangent integration leaves
  // one by design), so only a linear law's residual measures the solve.
  const double residual = fe.solution().residual;
  if constexpr (Fe::Law::kLinear)
    if (residual > times.equilibrium) times.equilibrium = residual, times.equilibrium_step = step;
  keep_largest(times.step_residual, step, residual);
  const Balance& balance = fe.solution().balance;
  keep_largest(times.step_balance, step, balance.relative());
  if (balance.relative() > times.balance) times.balance = balance.relative(), times.balance_step = step;
  times.last_balance = balance;
  const auto start   = std::chrono::steady_clock::now();
  if (const Subdomain* part = fe.problem().subdomain.get()) {
    const Solution whole = gather_solution(*part, fe.solution());
    auto values          = gather_cells(*part, fe.centroid_values(Recovered::stress), Recovered::stress);
    if (files) files->write(step, inc, whole, values, std::move(extra_cells), summary);
  } else if (files) {
    files->write(step, inc, fe.solution(), fe.centroid_values(Recovered::stress), std::move(extra_cells),
                 summary);
  }
  times.write += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress_line(r, step);
}

/// The result files of a run (the deck's output options and the pictures it asks for), on the process that
/// writes them.
inline RunFiles step_files(const RunRequest& r) {
  RunFiles files;
  if (!r.writes) return files;
  files.emplace(r.dir, r.scene, r.deck.step_time(), increments(r.deck.options.output_csv),
                increments(r.deck.options.output_vtu));
  files->draw_fields(r.pictures, r.units);
  files->keep_history(r.deck.steps(), {r.deck.options.friction_model() != "none", r.variant == "saga"});
  return files;
}

/// The end of a run, however it ends: the held increment (output = last), deformed.svg and the pictures,
/// timed as writing. A run that fails (a step Newton cannot take) still leaves them for the increments it
/// accepted; an error while writing them then gives way to the run's own.
struct FinishFiles {
  const RunRequest& r;
  RunTimes& times;
  RunFiles& files;
  bool done = false;

  void now() {
    done = true;
    progress_done(r);
    if (!files) return;
    const auto start = std::chrono::steady_clock::now();
    files->finish(r.deck.title);
    times.pictures = files->pictures_written(), times.pictures_skipped = files->pictures_skipped();
    times.write += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  ~FinishFiles() {
    if (done) return;
    try {
      now();
    } catch (...) {
    }
  }
};

}  // namespace gapfe::cli

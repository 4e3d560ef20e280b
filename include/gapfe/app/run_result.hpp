#pragma once
// A run's result as the report reads it (app/report.hpp): what run() returns besides its files.
#include <string>
#include <vector>

#include "gapfe/app/read_quantities.hpp"
#include "gapfe/contact/pair_state.hpp"
#include "gapfe/core/concepts.hpp"
#include "gapfe/problem/results.hpp"

namespace gapfe::app {

/// What a run did: wall-clock seconds of its phases after meshing, the work of contact and plasticity, and
/// the figures the report checks (residuals, global balance, friction cone, time error).
struct RunResult {
  /// `recovery`: the centroid stresses the files and the checks read, and the error estimate from the same
  /// pass when it runs (post/error_estimate.hpp).
  double assemble = 0, factorize = 0, solve = 0, write = 0, recovery = 0;
  /// The seconds the files took to write, whichever thread wrote them (RunFiles::write); `write` is the time
  /// the run waited for them.
  double files_seconds = 0;
  bool files_beside    = false;  ///< increments' files were written beside the next increment's work
  FactorStatistics factor;       ///< the last factorization's size and work (when the solver counts them)
  /// The recovery estimate of the discretization error (post/error_estimate.hpp): per load step (index
  /// step - 1) the largest relative energy-norm error of its accepted increments; the last increment's, with
  /// the deck element (0-based) that holds its largest share and that element's corners' mean (r, z).
  std::vector<double> step_error;
  double error           = 0;
  int error_element      = -1;
  Vec2 error_element_at  = Vec2::Zero();
  bool error_stress_free = false;  ///< the last increment's stresses are round-off: nothing to estimate
  /// The last increment's quantities, when the request asks for them (RunRequest::read_quantities).
  std::vector<ReadQuantity> quantities;
  ContactCounters contact;
  int increments = 0, closed = 0, pairs = 0;
  double penalty        = 0;
  int newton_iterations = 0, cut_steps = 0, plastic_points = 0, factorizations = 0;
  int element_passes = 0, tangents = 0;  ///< Newton's F_int evaluations, and those that assembled K_t
  int stalled  = 0;  ///< increments accepted at round-off (NewtonOptions::stall_factor), not the tolerance
  double drift = 0, worst_residual = 0;
  double time_error =
      0;  ///< rate-dependent laws: the largest StepReport::time_error of an accepted increment
  /// Linear laws: the largest |K u - f| / |f| over the free DOFs of an accepted increment's solve
  /// (ill-conditioning shows here, as round-off the factorization could not hold), and its load step.
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

}  // namespace gapfe::app

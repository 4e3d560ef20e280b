#pragma once
// The options of a contact analysis (ContactStatic, driver/contact_static.hpp), and their checks.
#include <cmath>
#include <vector>

#include "gapfe/core/error.hpp"

namespace gapfe {

struct ContactOptions {
  double penalty_factor = 0;            ///< kappa; 0: the policy's kDefaultPenalty
  std::vector<int> gap_materials;       ///< material indices of gap elements, left out of the penalty scale
  double penetration_tolerance = 1e-8;  ///< augmented Lagrangian: |g| of closed pairs <= this x max |u|
  int max_multiplier_updates   = 200;   ///< per solve, before the run fails
  double max_soft_share        = 1e-2;  ///< open gap element stiffness / adjacent stiffness allowed
  double friction              = 0;     ///< mu >= 0 (models other than NoFriction)
  /// Laws that estimate a time error (StepReport::time_error): an increment longer than the smallest piece
  /// (kSmallestTimePiece of a load step) whose estimate exceeds this is not accepted: accept() throws
  /// TimeErrorExceeded (run_scene_contact restarts and repeats the piece in halves). 0: off.
  double time_tolerance = 0;
  /// Coulomb: k_t / adjacent stiffness; 0: the normal penalty factor (k_t = k). Proportional and
  /// Extended take theirs from the seed (mu k and k).
  double tangential_penalty_factor = 0;
  double friction_tolerance        = 1e-10;  ///< Coulomb: pair force imbalance / pair force to stop at
  int max_friction_iterations      = 40;     ///< Coulomb: Newton iterations per solve, then a SolveError
  /// Coulomb: leave the slip's unsymmetric coupling out of the pair tangents even when the solver reads
  /// every entry (always so for a symmetric solver). Newton then converges linearly; the tests measure it.
  bool symmetric_tangent = false;
  /// Exact policies: split the step at every status change, so closure loads are exact (true, the
  /// default), or let the statuses settle at the step's end by active-set rounds, without splitting
  /// (false; deck key `events = step-end`): far fewer solves on a path with many closures, at an O(step)
  /// error of a path-dependent response (friction, plasticity) that the friction benchmarks measure.
  bool locate_events = true;
  /// Time one unit of load factor lasts [model time unit], for rate-dependent laws: the deck's card 0
  /// delta t. A split or cut piece of a step lasts its fraction, so the rate stays what the load asks.
  double step_time = 1;
};

/// InputError for options no run can use: a load step that lasts no time, a negative or non-finite mu.
inline void check_options(const ContactOptions& o) {
  if (!(o.step_time > 0) || !std::isfinite(o.step_time))
    throw InputError("contact: the time a load step lasts must be a positive number");
  if (!(o.friction >= 0) || !std::isfinite(o.friction))
    throw InputError("friction: the coefficient mu must be a number >= 0");
}

}  // namespace gapfe

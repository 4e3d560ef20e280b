#pragma once
// How NonlinearStatic's Newton iterations start and stop (driver/nonlinear_static.hpp).

namespace gapfe {

/// The smallest piece of a load step (in load factor) that the drivers cut a rate-dependent law's steps to
/// by their time error (StepReport::time_error; run_scene_plastic, ContactStatic).
inline constexpr double kSmallestTimePiece = 1.0 / 1024;

/// Newton's stopping rule and starting point.
struct NewtonOptions {
  double tolerance   = 1e-10;  ///< |R_free| / |F_int| to stop at (|F_int| or the step's loads) [-]
  int max_iterations = 30;     ///< a SolveError beyond this (the caller may cut the step)
  /// Laws with kIterate: start a step from the last accepted step's displacement change, scaled by the
  /// ratio of the steps' dt (context()), instead of from the committed displacements (the prescribed
  /// values are then set at once). On the plastic tube of BENCHMARKS.md the first residual
  /// falls from about 1e-1 to 5e-3 and 45 solves become 27; the converged answer is the same to the
  /// tolerance. No extrapolation before a first accepted step, or when either dt is zero; a step whose
  /// extrapolated start fails restarts from the committed state (solve()).
  bool extrapolate = true;
  /// Laws with kIterate: an evaluation that Newton's quadratic rate says will end the step computes F_int
  /// without K_t, which no solve would use (NonlinearStatic::converged_next). Same iterates either way.
  bool predict_convergence = true;
  /// Accept a step whose residual has stopped falling (no new minimum below half the previous one in
  /// three iterations) once it is below stall_factor x tolerance: the round-off of a nearly singular
  /// tangent. Measured on the plastic tube with hardening c = 1 MPa (E / 2e5) at 3 p_L: the residuals
  /// wander between 1.5e-10 and 2.6e-10 for 30 iterations against 1e-10, and the step fails even when
  /// cut to 1/64. StepReport::stalled says so. 0 disables it (then only `tolerance` ends a step).
  double stall_factor = 100;
};

}  // namespace gapfe

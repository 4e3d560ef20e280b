#pragma once
// The record of one gap pair that a contact run keeps in its History (core/history.hpp) and writes out
// (gaps.csv, output/step_files.hpp), and the work counters of a run. Forces are total ring forces,
// compressive positive; gaps are positive open (core/types.hpp). Tangential quantities are in the pair's
// tangent plane (T, S = theta) of contact/friction.hpp.
#include <limits>
#include <vector>

#include "gapfe/core/types.hpp"

namespace gapfe {

/// State of one gap pair.
struct PairState {
  bool closed          = false;
  double gap           = 0;   ///< [length]
  double normal_force  = 0;   ///< P [force]
  double multiplier    = 0;   ///< lambda (augmented Lagrangian) [force]
  double reference_gap = 0;   ///< g_ref: the penalty acts on g - g_ref [length]
  double closed_at     = -1;  ///< load factor at which it last closed (-1: never)
  // Friction (contact/friction.hpp); zero without it.
  Vec2 slide = Vec2::Zero();  ///< s = (T, S) components of u_b - u_a [length]
  /// s_n: the slide the tangential spring of this increment starts from: the accepted slide, or, for a
  /// pair that closes inside a step whose statuses settle at its end, the slide at its interpolated
  /// closure point [length]
  Vec2 slide_start      = Vec2::Zero();
  Vec2 tangential_force = Vec2::Zero();  ///< t on node b [force]
  Vec2 tangential_base  = Vec2::Zero();  ///< t_base: accepted force, or the tangential multiplier [force]
  bool slipping         = false;         ///< the step's status (Coulomb: the return mapping's answer)
  double slip           = 0;             ///< relative tangential travel summed over slipping steps [length]
};

/// How far a state's friction forces stand from Coulomb's cone |t| <= mu P: the largest |t| / (mu P) over
/// the closed pairs, and the pair it belongs to. Coulomb keeps it at or below 1; the seed's models
/// (SAACFR's springs without a limit, the extended model's one-step-late status) can pass it. A closed
/// pair that carries a friction force without compression (P <= 0) is outside every cone: infinity.
struct ConeExcess {
  double ratio = 0;   ///< [-]; 0 where no closed pair carries a friction force
  int pair     = -1;  ///< index into the pairs; -1 with ratio 0
};

inline ConeExcess cone_excess(const std::vector<PairState>& states, double mu) {
  ConeExcess worst;
  for (std::size_t p = 0; p < states.size(); ++p) {
    const PairState& s = states[p];
    const double t     = s.tangential_force.norm();
    if (!s.closed || !(t > 0)) continue;
    const double ratio =
        s.normal_force > 0 && mu > 0 ? t / (mu * s.normal_force) : std::numeric_limits<double>::infinity();
    if (ratio > worst.ratio) worst = {ratio, static_cast<int>(p)};
  }
  return worst;
}

/// Work of the steps since the last reset, for the speed/accuracy tables.
struct ContactCounters {
  int solves = 0, factorizations = 0, splits = 0, multiplier_updates = 0;
  int friction_iterations = 0;  ///< Newton iterations of the pair forces (Coulomb), over all solves
  int friction_stalls     = 0;  ///< solves whose pair Newton stopped stalled (below 1e-4, not 1e-10)
  int cuts                = 0;  ///< solves that did not converge and were retried over half the interval
  int status_rounds       = 0;  ///< re-solves after statuses changed at the same load factor (events =
                                ///< step-end's settling; saac's pulling pairs opened)
};

}  // namespace gapfe

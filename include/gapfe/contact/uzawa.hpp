#pragma once
// The augmented-Lagrangian (Uzawa) updates of a contact solve (contact/policies.hpp, AugmentedLagrangian):
// lambda <- lambda - k g on closed pairs, re-solved with the same factorization, until every closed pair's
// |g| <= penetration_tolerance x max |u| (docs/theory.md 5.5 item 2). With friction the tangential force gets
// its own multiplier, t_base <- t, until every sticking pair's slide in the step is within the same
// tolerance (exact stick without a huge k_t).
#include <algorithm>
#include <cmath>
#include <string>

#include "gapfe/contact/pair_set.hpp"

namespace gapfe {

/// The largest violation among the closed trial pairs: |g|, and with friction a sticking pair's slide in
/// the step [length].
template <class PairSet>
double largest_violation(const PairSet& pairs, bool friction) {
  double worst = 0;
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const PairState& s = pairs.history().trial(p);
    if (!s.closed) continue;
    worst = std::max(worst, std::abs(s.gap));
    if (friction && !s.slipping) worst = std::max(worst, (s.slide - s.slide_start).norm());
  }
  return worst;
}

/// Update every closed trial pair's multipliers: lambda takes the normal force; a sticking pair's
/// tangential base its force. A slipping pair keeps the accepted base: the cone sets its force (re-basing
/// on mu P nu made Newton flip the slip direction back and forth on the press-fit path).
template <class PairSet>
void update_multipliers(PairSet& pairs) {
  for (std::size_t p = 0; p < pairs.size(); ++p)
    if (PairState& s = pairs.history().trial(p); s.closed) {
      s.multiplier = s.normal_force;
      if (!s.slipping) PairSet::rebase(s);
    }
}

/// Uzawa updates until `largest_violation` <= `tolerance()` (re-read after every solve: it scales with |u|):
/// `resolve()` re-evaluates the pairs and solves again with the factorization it has. `fail(why)` when
/// `max_updates` updates do not get there. Returns the number of updates.
template <class PairSet, class Tolerance, class Resolve, class Fail>
int uzawa_updates(PairSet& pairs, bool friction, int max_updates, Tolerance&& tolerance, Resolve&& resolve,
                  Fail&& fail) {
  for (int it = 0;; ++it) {
    const double worst = largest_violation(pairs, friction);
    if (worst <= tolerance()) return it;
    if (it == max_updates)
      fail("the augmented-Lagrangian updates did not reach the penetration tolerance (" +
           std::to_string(worst) + " after " + std::to_string(it) + " updates)");
    update_multipliers(pairs);
    resolve();
  }
}

}  // namespace gapfe

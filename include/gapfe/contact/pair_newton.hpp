#pragma once
// Newton on the pair forces of Coulomb friction over an elastic structure (contact/friction.hpp). The
// element system is linear, so a solve with the links linearized at the last iterate is a full Newton step,
// and the residual of the whole system lives at the pairs: the structure balances the linearized pair
// forces L(d) = F - K d of the links it was solved with, so R = L(d) - f(d) pair by pair
// (GapPairSet::imbalance). Each pair is linearized on the branch of the return mapping it is predicted to
// end on (GapPairSet::evaluate_at), which keeps Newton from cycling between slip directions.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "gapfe/contact/pair_set.hpp"

namespace gapfe {

struct PairNewtonOptions {
  double tolerance   = 1e-10;  ///< |R| / |f| to stop at
  int max_iterations = 40;     ///< solves, then fail
};

/// Iterate after a solve: `resolve()` sets the pairs' links again (update_links), solves the structure
/// with them and re-evaluates the pairs (and counts its solve: a failure below keeps the count). Each
/// imbalance goes into `residuals` (cleared first) as it is reached. Stops at the tolerance, or stalled:
/// below 1e-4 for four solves, pairs that have just closed carry forces so small that their stick/slip
/// status and slip direction are decided at round-off, and their force is right to that fraction of the
/// pair forces. `fail(why)` past max_iterations (`where`: the load factor, for the message). Returns
/// whether it stopped stalled.
template <class PairSet, class Resolve, class Fail>
bool pair_newton(const PairSet& pairs, const PairNewtonOptions& o, double where,
                 std::vector<double>& residuals, Resolve&& resolve, Fail&& fail) {
  auto& r = residuals;
  r.clear();
  for (int it = 0;; ++it) {
    r.push_back(pairs.imbalance(o.tolerance));
    const double now = r.back();
    if (now <= o.tolerance) return false;
    if (it >= 4 && now <= 1e-4 && now >= 0.5 * *std::min_element(r.end() - 5, r.end() - 1)) return true;
    if (it + 1 >= o.max_iterations) {
      std::ostringstream text;
      text << "the friction iterations did not converge in " << o.max_iterations << " solves at load factor "
           << where << " (relative pair force imbalances";
      for (const double x : r) text << ' ' << x;
      text << "; tolerance " << o.tolerance << "): cut the load step";
      fail(text.str());
    }
    resolve();
  }
}

}  // namespace gapfe

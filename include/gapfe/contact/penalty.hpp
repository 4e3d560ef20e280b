#pragma once
// The penalties of gap pairs (docs/theory.md 5.4): a pair's k is kappa times the stiffness of the structure
// next to it along its closure direction, max(n^T K_aa n, n^T K_bb n), K_aa node a's diagonal block of the
// structural (non-gap) elements; and the tolerances a contact run decides statuses with.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/core/types.hpp"

namespace gapfe {

/// Per pair, max(n^T K_aa n, n^T K_bb n) from the nodes' diagonal blocks `nodal` (zero-padded to 3 x 3);
/// InputError for a pair neither of whose nodes belongs to a structural element.
inline std::vector<double> adjacent_stiffness(const std::vector<Mat33>& nodal,
                                              const std::vector<GapPair>& pairs) {
  std::vector<double> adjacent;
  for (const GapPair& p : pairs) {
    const Vec3 n(p.normal(0), p.normal(1), 0.0);
    const double a = std::max(n.dot(nodal[p.node_a] * n), n.dot(nodal[p.node_b] * n));
    if (!(a > 0))
      throw InputError("gap element " + std::to_string(p.element + 1) + ": neither node " +
                       std::to_string(p.node_a + 1) + " nor " + std::to_string(p.node_b + 1) +
                       " belongs to a structural element, so there is nothing to scale its penalty by");
    adjacent.push_back(a);
  }
  return adjacent;
}

/// An open gap element must be soft: its own stiffness along N (from its nodes' blocks `soft`) resists
/// closure and shifts the closure load by about its share of the pair's penalty k (seed 2.2: "small
/// relative to the adjacent structure"). InputError past `max_share` (kappa: the penalty factor k was made
/// with, so the share is that of the adjacent stiffness).
inline void check_soft_gaps(const std::vector<GapPair>& pairs, const std::vector<Mat33>& soft, double kappa,
                            const std::vector<double>& k, double max_share) {
  for (std::size_t q = 0; q < pairs.size(); ++q) {
    const GapPair& p = pairs[q];
    const Vec3 n(p.normal(0), p.normal(1), 0.0);
    const double share = std::max(n.dot(soft[p.node_a] * n), n.dot(soft[p.node_b] * n)) * kappa / k[q];
    if (share > max_share) {
      char text[48];
      std::snprintf(text, sizeof text, "%.3g", share);
      throw InputError("gap element " + std::to_string(p.element + 1) + ": while open it is " + text +
                       " times as stiff along its closure direction as the structure next to it, so it "
                       "would carry load across the gap; lower the gap material's moduli");
    }
  }
}

/// Below minus this an open pair overlaps [length]: 1e-12 of the model size, or 1e-6 of the smallest
/// initial clearance where that is smaller. Without the second a 1e-13 m gap in a 0.1 m body was crossed by
/// its own size before it counted as closed (closure load 29-50% late; tests/test_contact.cpp, gaps to
/// 1e-12 of the body). A gap's round-off, ~1e-16 of the displacements across it, stays far below either.
inline double gap_tolerance_of(const std::vector<GapPair>& pairs, double model_size) {
  double tolerance = 1e-12 * model_size;
  for (const auto& g : pairs)
    if (g.initial_gap > 0) tolerance = std::min(tolerance, 1e-6 * g.initial_gap);
  return tolerance;
}

}  // namespace gapfe

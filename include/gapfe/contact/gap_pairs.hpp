#pragma once
// Gap elements and their node pairs (seed section 2.2-2.3, Eq. 1-7; docs/theory.md 5.1).
//
// A gap element is a cell of soft material (material 2 in a deck) between two bodies. Its principal gap
// direction (the seed's LGAP in SAAC, IJDIR per material block in SAAC2) says which corners face each
// other across the gap. With the corners in the seed's order IX1..IX4 = (I, J), (I+1, J), (I+1, J+1),
// (I, J+1):
//   1: the gap runs along J and closes along I; pairs IX1 -> IX2 and IX4 -> IX3, mean-line ends
//      A = (IX1 + IX4) / 2 and B = (IX2 + IX3) / 2 (Eq. 1-2);
//   2: the gap runs along I and closes along J; pairs IX1 -> IX4 and IX2 -> IX3, A = (IX1 + IX2) / 2,
//      B = (IX4 + IX3) / 2;
//   0: none: the element keeps its soft stiffness throughout (SAAC2's corner elements).
// The gap angle is beta = atan2(R_B - R_A, Z_B - Z_A) (Eq. 3, with atan2 for the quadrant), so the
// closure direction N = (sin beta, cos beta) in (r, z) is the unit vector from A to B, T = (-cos beta,
// sin beta) runs along the gap and S = e_theta (Eq. 5). A pair's gap is g = N . (x_b - x_a) + N . (u_b -
// u_a) [length]: positive open, zero touching, negative overlapping. Beta stays at its initial value
// (small displacements; the seed updates positions along N only, which is the same thing).
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/types.hpp"

namespace gapfe {

struct GapPair {
  int element = 0;                    ///< the gap element's number (0-based; a deck's element numbering)
  int pair    = 0;                    ///< 0: the pair of the seed's contact state 2, 1: of state 3
  int node_a = 0, node_b = 0;         ///< face A -> face B (0-based mesh nodes)
  Vec2 normal        = Vec2::Zero();  ///< N = (sin beta, cos beta), closure direction from A to B
  double initial_gap = 0;             ///< g0 = N . (x_b - x_a) [length], >= 0

  /// Gap under the relative displacement u_b - u_a (r, z components) [length].
  double gap(const Vec2& relative) const { return initial_gap + normal.dot(relative); }
  /// T = (-cos beta, sin beta) in (r, z): along the gap, the in-plane direction friction acts in.
  Vec2 tangent() const { return {-normal(1), normal(0)}; }
  /// The gap angle beta of Eq. 3 [rad].
  double beta() const { return std::atan2(normal(0), normal(1)); }
};

/// The two pairs of a gap element with corners `ix` in the seed's order and direction 1 or 2.
inline std::array<GapPair, 2> gap_element_pairs(int element, const std::array<int, 4>& ix, int direction,
                                                const std::vector<Vec2>& nodes) {
  const std::string where = "gap element " + std::to_string(element + 1);
  if (direction != 1 && direction != 2)
    throw InputError(where + ": gap direction must be 1 (closure along I) or 2 (along J), got " +
                     std::to_string(direction));
  // (a, b) of each pair: face A is the IX1 side.
  const std::array<std::array<int, 2>, 2> p = direction == 1
                                                  ? std::array<std::array<int, 2>, 2>{{{0, 1}, {3, 2}}}
                                                  : std::array<std::array<int, 2>, 2>{{{0, 3}, {1, 2}}};
  const Vec2 a                              = 0.5 * (nodes[ix[p[0][0]]] + nodes[ix[p[1][0]]]);
  const Vec2 b                              = 0.5 * (nodes[ix[p[0][1]]] + nodes[ix[p[1][1]]]);
  const double length                       = (b - a).norm();
  double size                               = 0;
  for (int k = 0; k < 4; ++k) size = std::max(size, (nodes[ix[k]] - nodes[ix[(k + 1) % 4]]).norm());
  if (!(length > 1e-14 * size))
    throw InputError(where + ": the mean line from face A to face B has zero length, so the gap angle " +
                     "(seed Eq. 3) is undefined");
  const Vec2 normal = (b - a) / length;
  std::array<GapPair, 2> out;
  for (int k = 0; k < 2; ++k) {
    GapPair& g = out[k];
    g.element = element, g.pair = k, g.node_a = ix[p[k][0]], g.node_b = ix[p[k][1]], g.normal = normal;
    g.initial_gap = normal.dot(nodes[g.node_b] - nodes[g.node_a]);
    if (g.initial_gap < 0)
      throw InputError(where + ": nodes " + std::to_string(g.node_a + 1) + " and " +
                       std::to_string(g.node_b + 1) + " overlap by " + std::to_string(-g.initial_gap) +
                       " along the closure direction; a gap must start open or touching");
  }
  return out;
}

}  // namespace gapfe

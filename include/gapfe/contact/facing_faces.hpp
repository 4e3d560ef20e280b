#pragma once
// Gap elements from two facing faces: where a mesh gives the two sides of a gap as curves (a
// scene file's [[contact]] faces) instead of a deck's column of material-2 cells, the node pairs come from
// the faces' positions, and each edge of face A with its two partners is one gap element of the seed's kind
// (gap_pairs.hpp: corners IX1..IX4 = a, partner(a), partner(b), b with gap direction 1, so Eq. 1-3 give its
// pairs and its normal, from mid-face A to mid-face B).
//
// Pairing: every node of face A pairs with the node of face B nearest to it, which must lie closer than
// half of the shortest face edge at either node (so a gap much thinner than the elements pairs unambiguously)
// and must not be the partner of another node of A; every node of B must be some node's partner. Both faces
// therefore need the same node distribution and their own nodes (a node on both faces is refused: a gap
// needs two sides). Each failure is an InputError naming the node, its position and the nearest candidate.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/types.hpp"

namespace gapfe {

/// The gap elements between faces A and B: edges as node pairs (0-based indices into `x`); `labels` name
/// the nodes in messages (a Gmsh tag), `name_a`, `name_b` the faces. Returns the corners of one gap
/// element per edge of A, in the seed's order for gap direction 1.
inline std::vector<std::array<int, 4>> facing_gap_elements(const std::vector<Vec2>& x,
                                                           const std::vector<std::array<int, 2>>& edges_a,
                                                           const std::vector<std::array<int, 2>>& edges_b,
                                                           const std::string& name_a,
                                                           const std::string& name_b,
                                                           const std::vector<long>& labels) {
  // The shortest edge at each node of each face: the pairing tolerance is half of it.
  std::map<int, double> reach_a, reach_b;
  const auto reach = [&](const std::vector<std::array<int, 2>>& edges, std::map<int, double>& shortest) {
    for (const auto& e : edges) {
      const double length = (x[e[1]] - x[e[0]]).norm();
      for (const int n : e) {
        auto [it, fresh] = shortest.emplace(n, length);
        if (!fresh) it->second = std::min(it->second, length);
      }
    }
  };
  reach(edges_a, reach_a), reach(edges_b, reach_b);
  const auto node_text = [&](int n) {
    return "node " + std::to_string(labels[n]) + " (r = " + detail::number_text(x[n](0)) +
           ", z = " + detail::number_text(x[n](1)) + ")";
  };
  for (const auto& [n, length] : reach_a)
    if (reach_b.count(n))
      throw InputError(node_text(n) + " is on both faces \"" + name_a + "\" and \"" + name_b +
                       "\"; a gap needs each face its own nodes (mesh the two curves apart, or duplicate the "
                       "interface's nodes)");
  // The nearest node of face B through buckets as wide as the longest edge: a partner within half an edge
  // is in a neighbouring bucket.
  double width = 0;
  for (const auto* r : {&reach_a, &reach_b})
    for (const auto& [n, length] : *r) width = std::max(width, length);
  if (!(width > 0)) throw InputError("the faces \"" + name_a + "\" and \"" + name_b + "\" have no length");
  const auto bucket = [&](int n) {
    return std::pair<long, long>{std::lround(std::floor(x[n](0) / width)),
                                 std::lround(std::floor(x[n](1) / width))};
  };
  std::map<std::pair<long, long>, std::vector<int>> buckets_b;
  for (const auto& [n, length] : reach_b) buckets_b[bucket(n)].push_back(n);
  const auto nearest_b = [&](int a) {
    std::pair<int, double> best{-1, std::numeric_limits<double>::infinity()};
    const std::pair<long, long> home = bucket(a);
    for (long i = home.first - 1; i <= home.first + 1; ++i)
      for (long j = home.second - 1; j <= home.second + 1; ++j)
        if (const auto it = buckets_b.find({i, j}); it != buckets_b.end())
          for (const int b : it->second)
            if (const double d = (x[b] - x[a]).norm(); d < best.second) best = {b, d};
    if (best.first < 0)  // none nearby: the nearest anywhere, for the message
      for (const auto& [b, length] : reach_b)
        if (const double d = (x[b] - x[a]).norm(); d < best.second) best = {b, d};
    return best;
  };
  std::map<int, int> partner, faced_by;  // a -> b, b -> a
  for (const auto& [a, length_a] : reach_a) {
    const auto [b, d]      = nearest_b(a);
    const double tolerance = 0.5 * std::min(length_a, reach_b.at(b));
    if (!(d < tolerance))
      throw InputError(node_text(a) + " on face \"" + name_a + "\" has no node of face \"" + name_b +
                       "\" within half its shortest edge (" + detail::number_text(tolerance) +
                       "); the nearest is " + node_text(b) + ", " + detail::number_text(d) +
                       " away. The faces' nodes must face each other one to one: mesh both curves with the "
                       "same node distribution");
    if (const auto it = faced_by.find(b); it != faced_by.end())
      throw InputError(node_text(a) + " and " + node_text(it->second) + " on face \"" + name_a +
                       "\" both face " + node_text(b) + " on face \"" + name_b +
                       "\"; the faces' nodes must face each other one to one");
    partner[a] = b, faced_by[b] = a;
  }
  for (const auto& [b, length] : reach_b)
    if (!faced_by.count(b))
      throw InputError(node_text(b) + " on face \"" + name_b + "\" faces no node of face \"" + name_a +
                       "\" (" + std::to_string(reach_a.size()) + " nodes on \"" + name_a + "\", " +
                       std::to_string(reach_b.size()) + " on \"" + name_b + "\")");
  std::vector<std::array<int, 4>> corners;
  corners.reserve(edges_a.size());
  for (const auto& e : edges_a) corners.push_back({e[0], partner.at(e[0]), partner.at(e[1]), e[1]});
  return corners;
}

}  // namespace gapfe

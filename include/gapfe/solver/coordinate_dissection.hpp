#pragma once
// coordinate_dissection: a nested-dissection ordering of a mesh's nodes from their coordinates
// (recursive coordinate bisection): split the part at the median coordinate along its longer extent;
// the nodes on the upper side that touch the lower side are the separator, eliminated after both halves,
// which recurse. On an I-J grid the cut falls between two grid lines and the separator is one line, the
// ordering George (1973) proved optimal for the 5- and 9-point grid: O(n log n) fill and O(n^1.5) work.
//
// Why it exists (BENCHMARKS.md, "Levers, each measured"): on the 1e6-equation tube CHOLMOD's AMD needs 1.8e11
// flops and 1.64e8 entries of L; METIS needs 5.7e10 and 1.05e8 but takes 4.6 s to find them, as long as the
// factorization it saves. The coordinates make the same cuts in a few hundredths of a second.
//
// Input: node coordinates and the node adjacency (CSR: neighbours of n are adj[ptr[n] .. ptr[n + 1]));
// output: the nodes in elimination order (order[k] = the node eliminated k-th). Any permutation is a
// valid ordering, so a poor cut (a mesh far from a grid) costs fill, never correctness.
#include <algorithm>
#include <vector>

#include "gapfe/core/types.hpp"

namespace gapfe {

inline std::vector<int> coordinate_dissection(const std::vector<Vec2>& x, const std::vector<int>& ptr,
                                              const std::vector<int>& adj) {
  constexpr std::size_t kLeaf = 64;  // parts this small keep their order: fill inside is negligible
  const int n                 = static_cast<int>(x.size());
  std::vector<int> order;
  order.reserve(x.size());
  std::vector<int> side(x.size(), 0);  // per node: 1 lower half, 2 upper half, during one split
  struct Part {
    std::vector<int> nodes;
    bool separator;  // a separator waiting for its two halves to be ordered
  };
  std::vector<int> all(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) all[static_cast<std::size_t>(i)] = i;
  // Depth-first with an explicit stack (a 1e6-node grid nests about 40 levels; no recursion limit).
  std::vector<Part> stack;
  stack.push_back({std::move(all), false});
  std::vector<double> key;
  while (!stack.empty()) {
    Part part = std::move(stack.back());
    stack.pop_back();
    std::vector<int>& v = part.nodes;
    if (part.separator || v.size() <= kLeaf) {
      order.insert(order.end(), v.begin(), v.end());
      continue;
    }
    Vec2 lo = x[static_cast<std::size_t>(v.front())], hi = lo;
    for (const int i : v)
      lo = lo.cwiseMin(x[static_cast<std::size_t>(i)]), hi = hi.cwiseMax(x[static_cast<std::size_t>(i)]);
    const int axis = (hi - lo)(0) >= (hi - lo)(1) ? 0 : 1;
    key.resize(v.size());
    for (std::size_t k = 0; k < v.size(); ++k) key[k] = x[static_cast<std::size_t>(v[k])](axis);
    std::nth_element(key.begin(), key.begin() + static_cast<std::ptrdiff_t>(key.size() / 2), key.end());
    const double median = key[key.size() / 2];
    // Lower: strictly below the median value (a grid line is never cut); when that leaves nothing below,
    // split by rank instead.
    std::vector<int> lower, upper;
    for (const int i : v) (x[static_cast<std::size_t>(i)](axis) < median ? lower : upper).push_back(i);
    if (lower.empty() || upper.empty()) {
      std::sort(v.begin(), v.end(), [&](int a, int b) {
        return x[static_cast<std::size_t>(a)](axis) < x[static_cast<std::size_t>(b)](axis);
      });
      lower.assign(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2));
      upper.assign(v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    }
    for (const int i : lower) side[static_cast<std::size_t>(i)] = 1;
    for (const int i : upper) side[static_cast<std::size_t>(i)] = 2;
    std::vector<int> separator, rest;
    for (const int i : upper) {
      bool touches = false;
      for (int k = ptr[static_cast<std::size_t>(i)]; k < ptr[static_cast<std::size_t>(i) + 1] && !touches;
           ++k)
        touches = side[static_cast<std::size_t>(adj[static_cast<std::size_t>(k)])] == 1;
      (touches ? separator : rest).push_back(i);
    }
    for (const int i : v) side[static_cast<std::size_t>(i)] = 0;
    // Pushed in reverse: lower half first, then the upper, then the separator.
    stack.push_back({std::move(separator), true});
    stack.push_back({std::move(rest), false});
    stack.push_back({std::move(lower), false});
  }
  return order;
}

}  // namespace gapfe

#pragma once
// top_split: where an elimination order lets a Cholesky factorization split in two. The equations
// eliminated last form a chain at the root of the elimination tree (a nested dissection's top separator)
// down to its first branching: everything eliminated before it falls into parts with no stiffness
// between them (the subtrees of that branching; no entry of K or of its factor couples two of them), so
// each part's columns of L can be computed on a thread of its own and only the separator's dense block
// waits for both (solver/split_cholmod.hpp).
//
// Found without the tree: the chain starts at the largest t for which the equations eliminated before
// position t are not connected (K's graph restricted to them has two or more components, none too large to
// make two even halves); a union-find over the order follows every t's components in one pass. They are then
// dealt to two halves, the largest first to the half with fewer equations (a nested dissection gives two).
#include <algorithm>
#include <array>
#include <numeric>
#include <vector>

#include "gapfe/core/types.hpp"

namespace gapfe {

/// The order's last equations (the separator, in the order's sequence) and the others in two halves with no
/// entry of K between them, each in a postorder of the elimination tree. Empty halves when the order has no
/// such split.
struct TopSplit {
  std::array<std::vector<int>, 2> halves;
  std::vector<int> separator;
  bool found() const { return !halves[0].empty() && !halves[1].empty(); }
};

namespace detail {

/// K's off-diagonal pattern (the lower triangle of `lower`) in elimination positions: for position j,
/// the positions i < j coupled to it, at earlier[start[j] .. start[j + 1]).
struct EarlierNeighbours {
  std::vector<int> start, earlier;
  EarlierNeighbours(const SpMat& lower, const std::vector<int>& position) : start(position.size() + 1, 0) {
    const auto later = [&](int r, int c) {
      return std::max(position[std::size_t(r)], position[std::size_t(c)]);
    };
    for (int c = 0; c < lower.outerSize(); ++c)
      for (SpMat::InnerIterator it(lower, c); it; ++it)
        if (it.index() != c) ++start[std::size_t(later(int(it.index()), c)) + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    earlier.resize(std::size_t(start.back()));
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int c = 0; c < lower.outerSize(); ++c)
      for (SpMat::InnerIterator it(lower, c); it; ++it)
        if (const int r = int(it.index()); r != c)
          earlier[std::size_t(fill[std::size_t(later(r, c))]++)] =
              std::min(position[std::size_t(r)], position[std::size_t(c)]);
  }
};

/// Union-find with path halving over positions.
struct Components {
  std::vector<int> parent;
  explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) {
    while (parent[std::size_t(a)] != a)
      a = parent[std::size_t(a)] = parent[std::size_t(parent[std::size_t(a)])];
    return a;
  }
  bool join(int a, int b) {
    a = find(a), b = find(b);
    if (a == b) return false;
    parent[std::size_t(std::max(a, b))] = std::min(a, b);
    return true;
  }
};

/// The elimination tree of K in elimination positions (Liu's algorithm with path compression): parent[j]
/// the position whose column first needs j's, -1 at a root.
inline std::vector<int> elimination_tree(const EarlierNeighbours& near) {
  const std::size_t n = near.start.size() - 1;
  std::vector<int> parent(n, -1), ancestor(n, -1);
  for (int j = 0; j < static_cast<int>(n); ++j)
    for (int k = near.start[std::size_t(j)]; k < near.start[std::size_t(j) + 1]; ++k)
      for (int i = near.earlier[std::size_t(k)], next; i != -1 && i < j; i = next) {
        next                     = ancestor[std::size_t(i)];
        ancestor[std::size_t(i)] = j;
        if (next == -1) parent[std::size_t(i)] = j;
      }
  return parent;
}

/// rank[j]: j's place in a postorder of the forest `parent` (children before parents, each subtree
/// contiguous; children and roots in increasing order).
inline std::vector<int> postorder_rank(const std::vector<int>& parent) {
  const int n = static_cast<int>(parent.size());
  std::vector<int> first(parent.size(), -1), next(parent.size(), -1), rank(parent.size(), -1), stack;
  for (int j = n - 1; j >= 0; --j)  // children lists in increasing order
    if (const int p = parent[std::size_t(j)]; p >= 0)
      next[std::size_t(j)] = first[std::size_t(p)], first[std::size_t(p)] = j;
  int k = 0;
  for (int root = 0; root < n; ++root) {
    if (parent[std::size_t(root)] >= 0) continue;
    stack.push_back(root);
    while (!stack.empty()) {
      const int j = stack.back();
      if (const int child = first[std::size_t(j)]; child >= 0) {
        first[std::size_t(j)] = next[std::size_t(child)];  // the next child on the next visit
        stack.push_back(child);
      } else {
        rank[std::size_t(j)] = k++;
        stack.pop_back();
      }
    }
  }
  return rank;
}

}  // namespace detail

/// The split of `order` (order[k] = the equation eliminated k-th) for K's lower triangle `lower` (see the
/// top). A split whose separator has more than max_separator equations, or whose smaller half has fewer
/// than min_share of the other equations, is no split.
inline TopSplit top_split(const SpMat& lower, const std::vector<int>& order, int max_separator,
                          double min_share) {
  const int n = static_cast<int>(order.size());
  TopSplit split;
  if (n < 3 || lower.rows() != n) return split;
  std::vector<int> position(std::size_t(n), 0);
  for (int k = 0; k < n; ++k) position[std::size_t(order[std::size_t(k)])] = k;
  const detail::EarlierNeighbours near(lower, position);
  detail::Components parts(static_cast<std::size_t>(n));
  // The split starts at the largest t at which no component of the first t positions' graph holds more
  // than 1 - 2 min_share of them: dealt out largest first, they then make halves of at least min_share
  // each (greedy's halves differ by at most the largest). A nested dissection's is its top separator; a small
  // body apart from the rest, a component through every t, does not hide it.
  std::vector<int> grown(static_cast<std::size_t>(n), 1);  // a component's size, at its root
  int largest = 0, start = -1;
  for (int j = 0; j <= n; ++j) {
    if (j >= 2 && largest <= (1 - 2 * min_share) * j) start = j;
    if (j == n) break;
    largest = std::max(largest, 1);
    for (int k = near.start[std::size_t(j)]; k < near.start[std::size_t(j) + 1]; ++k) {
      const int a = parts.find(near.earlier[std::size_t(k)]), b = parts.find(j);
      if (a == b) continue;
      parts.join(a, b);  // the smaller index becomes the root
      const int root           = std::min(a, b);
      grown[std::size_t(root)] = grown[std::size_t(a)] + grown[std::size_t(b)];
      largest                  = std::max(largest, grown[std::size_t(root)]);
    }
  }
  if (start < 0 || n - start > max_separator) return split;
  // The components of positions [0, start), sized, then dealt out (see the top).
  parts = detail::Components(static_cast<std::size_t>(start));
  for (int j = 0; j < start; ++j)
    for (int k = near.start[std::size_t(j)]; k < near.start[std::size_t(j) + 1]; ++k)
      parts.join(near.earlier[std::size_t(k)], j);
  std::vector<int> size(std::size_t(start), 0), roots;
  for (int j = 0; j < start; ++j)
    if (++size[std::size_t(parts.find(j))] == 1) roots.push_back(parts.find(j));
  std::sort(roots.begin(), roots.end(), [&](int a, int b) {
    return size[std::size_t(a)] != size[std::size_t(b)] ? size[std::size_t(a)] > size[std::size_t(b)] : a < b;
  });
  std::vector<signed char> half(std::size_t(start), 0);
  std::array<int, 2> count{0, 0};
  for (const int r : roots) {
    const int h          = count[1] < count[0] ? 1 : 0;
    half[std::size_t(r)] = static_cast<signed char>(h);
    count[std::size_t(h)] += size[std::size_t(r)];
  }
  if (std::min(count[0], count[1]) < min_share * start) return split;
  // Each half in a postorder of the elimination tree (its subtrees contiguous, a child before its parent),
  // which the supernodal analysis needs to find its supernodes: the halves are analyzed in their own order
  // (SplitCholmod). The separator is the tree's trunk, already in order.
  const std::vector<int> rank = detail::postorder_rank(detail::elimination_tree(near));
  std::vector<int> by_rank(std::size_t(start), -1);
  for (int j = 0; j < start; ++j) {
    if (rank[std::size_t(j)] >= start) return {};  // the trunk is not the tree's top: no split
    by_rank[std::size_t(rank[std::size_t(j)])] = j;
  }
  for (const int j : by_rank)
    split.halves[std::size_t(half[std::size_t(parts.find(j))])].push_back(order[std::size_t(j)]);
  split.separator.assign(order.begin() + start, order.end());
  return split;
}

}  // namespace gapfe

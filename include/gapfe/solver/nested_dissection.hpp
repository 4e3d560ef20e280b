#pragma once
// NestedDissectionOrdering: a fill-reducing ordering for Eigen's simplicial Cholesky, by recursive
// level-structure bisection (George's automatic nested dissection, as in George & Liu, "Computer
// Solution of Large Sparse Positive Definite Systems", ch. 8): in each part, breadth-first levels from
// a pseudo-peripheral vertex; the middle level is the separator and is eliminated last; the two sides
// recurse. On the 2-D meshes gapfe makes, separators are mesh lines across the body, and the factor
// needs markedly fewer operations than with minimum degree (BENCHMARKS.md). Parts smaller than
// kLeaf vertices keep their breadth-first (Cuthill-McKee-like) order.
//
// Eigen's ordering contract: operator()(C, perm) receives the full symmetric pattern C and returns
// perm with perm.indices()[k] = the original index of the k-th pivot (Eigen's m_Pinv).
#include <algorithm>
#include <vector>

#include <Eigen/SparseCore>

namespace gapfe {

struct NestedDissectionOrdering {
  static constexpr int kLeaf = 128;

  template <class MatrixType, class Permutation>
  void operator()(const MatrixType& c, Permutation& perm) const {
    const int n = static_cast<int>(c.cols());
    // Adjacency without the diagonal (C is column-major and symmetric).
    ptr_.assign(static_cast<std::size_t>(n) + 1, 0);
    adj_.clear();
    adj_.reserve(static_cast<std::size_t>(c.nonZeros()));
    for (int j = 0; j < n; ++j) {
      for (typename MatrixType::InnerIterator it(c, j); it; ++it)
        if (it.index() != j) adj_.push_back(static_cast<int>(it.index()));
      ptr_[j + 1] = static_cast<int>(adj_.size());
    }
    part_.assign(static_cast<std::size_t>(n), 0);  // part label of every vertex; 0 = the whole graph
    level_.assign(static_cast<std::size_t>(n), -1);
    order_.clear();
    order_.reserve(static_cast<std::size_t>(n));
    std::vector<int> all(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) all[i] = i;
    next_label_ = 1;
    dissect(all, 0);
    perm.resize(n);
    for (int k = 0; k < n; ++k)
      perm.indices()[k] = static_cast<typename Permutation::StorageIndex>(order_[k]);
  }

 private:
  /// Breadth-first levels of the vertices of `label` reachable from `root`; returns them in BFS order
  /// and leaves each one's level in level_.
  std::vector<int> bfs(int root, int label) const {
    std::vector<int> queue{root};
    level_[root] = 0;
    for (std::size_t h = 0; h < queue.size(); ++h) {
      const int v = queue[h];
      for (int k = ptr_[v]; k < ptr_[v + 1]; ++k) {
        const int w = adj_[k];
        if (part_[w] == label && level_[w] < 0) level_[w] = level_[v] + 1, queue.push_back(w);
      }
    }
    return queue;
  }
  void clear_levels(const std::vector<int>& vs) const {
    for (int v : vs) level_[v] = -1;
  }

  /// Order `vs` (all with part label `label`), appending to order_.
  void dissect(const std::vector<int>& vs, int label) const {
    if (static_cast<int>(vs.size()) <= kLeaf) {
      // Breadth-first order of each component.
      for (int v : vs)
        if (level_[v] < 0) {
          const auto comp = bfs(v, label);
          order_.insert(order_.end(), comp.begin(), comp.end());
        }
      for (int v : vs) level_[v] = -1, part_[v] = -1;
      return;
    }
    // Split into connected components first (each is dissected on its own, one recursion level).
    std::vector<std::vector<int>> comps;
    for (int v : vs)
      if (level_[v] < 0) comps.push_back(bfs(v, label));
    if (comps.size() > 1) {
      for (auto& c : comps) {
        clear_levels(c);
        const int l = next_label_++;
        for (int v : c) part_[v] = l;
      }
      for (auto& c : comps) dissect(c, part_[c.front()]);
      return;
    }
    std::vector<int> comp = std::move(comps.front());
    // Pseudo-peripheral root: repeat BFS from a far vertex of least degree while the depth grows.
    int root = vs.front(), depth = level_[comp.back()];
    for (int pass = 0; pass < 4; ++pass) {
      int best = comp.back();
      for (auto it = comp.rbegin(); it != comp.rend() && level_[*it] == depth; ++it)
        if (ptr_[*it + 1] - ptr_[*it] < ptr_[best + 1] - ptr_[best]) best = *it;
      clear_levels(comp);
      comp           = bfs(best, label);
      const int deep = level_[comp.back()];
      if (deep <= depth) {
        clear_levels(comp);
        comp = bfs(root, label);
        break;
      }
      root = best, depth = deep;
    }
    depth = level_[comp.back()];
    if (depth < 2) {  // no interior level to cut: a clique-like part
      order_.insert(order_.end(), comp.begin(), comp.end());
      for (int v : comp) level_[v] = -1, part_[v] = -1;
      return;
    }
    // Separator: the level where half of the vertices have been passed.
    const int mid = std::clamp(level_[comp[comp.size() / 2]], 1, depth - 1);
    std::vector<int> a, b, sep;
    for (int v : comp) (level_[v] < mid ? a : level_[v] > mid ? b : sep).push_back(v);
    clear_levels(comp);
    const int la = next_label_++, lb = next_label_++;
    for (int v : a) part_[v] = la;
    for (int v : b) part_[v] = lb;
    for (int v : sep) part_[v] = -1;  // ordered last, out of both halves
    dissect(a, la);
    dissect(b, lb);
    order_.insert(order_.end(), sep.begin(), sep.end());
  }

  mutable std::vector<int> ptr_, adj_, part_, level_, order_;
  mutable int next_label_ = 1;
};

}  // namespace gapfe

#pragma once
// Edge tractions (seed Data 13-15) onto nodal forces. A load names its edge by the two end nodes M -> N
// and the element must lie to its left (counterclockwise), so the index maps the ordered pair (start,
// end) of a cell edge to its cell; a load given the wrong way round gets an error that says so. Only the
// loads' edges are indexed, either way round: an index of every edge held a hash node per cell edge through
// the run (an estimated 80 MB at 1e6 equations; BENCHMARKS.md "Memory first").
#include <cstdint>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "gapfe/assembly/cells.hpp"
#include "gapfe/assembly/edge_loads.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/core/pair_key.hpp"

namespace gapfe {

/// The error of edge load k (0-based) whose edge M -> N is no element's: `reversed` when N -> M is one.
inline InputError edge_load_error(std::size_t k, const EdgeLoad& l, bool reversed) {
  const std::string what = "edge load " + std::to_string(k + 1) + " from node " +
                           std::to_string(l.node_m + 1) + " to node " + std::to_string(l.node_n + 1);
  if (reversed)
    return InputError(what + ": the element must lie to the left going from M to N; swap M and N");
  return InputError(what + ": the two nodes are not the ends of an element edge");
}

template <class Elem>
class EdgeIndex {
 public:
  /// Consistent forces of every edge load into `out` (all DOFs, DofsPerNode components per node).
  template <int DofsPerNode, class MeshT>
  void add_loads(const MeshT& m, const std::vector<EdgeLoad>& loads, VecX& out) {
    if (loads.empty()) return;
    if (!covers(loads)) build(m, loads);
    for (std::size_t k = 0; k < loads.size(); ++k) {
      const EdgeLoad& l = loads[k];
      const auto it     = edges_.find(pair_key(l.node_m, l.node_n));
      if (it == edges_.end()) throw edge_load_error(k, l, edges_.count(pair_key(l.node_n, l.node_m)) > 0);
      const auto [triangle, cell, edge] = it->second;
      if (!triangle) apply<Elem, DofsPerNode>(m.nodes, m.cells[cell], edge, l, out);
      if constexpr (kHasTriangles<Elem>)
        if (triangle) apply<typename Elem::Degenerate, DofsPerNode>(m.nodes, m.triangles[cell], edge, l, out);
    }
  }

 private:
  struct EdgeRef {
    bool triangle;
    std::size_t cell;
    int edge;
  };
  /// Whether the index was built for every edge of `loads` (the loads of a later step may name others).
  bool covers(const std::vector<EdgeLoad>& loads) const {
    for (const EdgeLoad& l : loads)
      if (wanted_.count(pair_key(l.node_m, l.node_n)) == 0) return false;
    return true;
  }
  /// The cells' edges that `loads` or earlier calls' loads name, either way round (the other way for the
  /// error's hint): steps that alternate between edges scan the cells once per new edge set, not per call.
  template <class MeshT>
  void build(const MeshT& m, const std::vector<EdgeLoad>& loads) {
    edges_.clear();
    for (const EdgeLoad& l : loads)
      wanted_.insert({pair_key(l.node_m, l.node_n), pair_key(l.node_n, l.node_m)});
    for_each_cell<Elem>(m, [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t e,
                                                         const std::array<int, NPC>& cell, const CellTag&) {
      for (int k = 0; k < static_cast<int>(E::kEdges.size()); ++k)
        if (const std::uint64_t key = pair_key(cell[E::kEdges[k].front()], cell[E::kEdges[k].back()]);
            wanted_.count(key) > 0)
          edges_[key] = {!std::is_same_v<E, Elem>, e, k};
    });
  }
  template <class E, int DofsPerNode, std::size_t NPC>
  static void apply(const std::vector<Vec2>& nodes, const std::array<int, NPC>& cell, int edge,
                    const EdgeLoad& l, VecX& out) {
    constexpr int en = E::kEdgeNodes;
    Mat<en, 2> x;
    std::array<int, en> node;
    // kEdges lists (start, end) for 2-node edges and (start, mid, end) for 3-node edges.
    for (int a = 0; a < en; ++a) node[a] = cell[E::kEdges[edge][a]], x.row(a) = nodes[node[a]].transpose();
    const Mat<en, 3> f = edge_forces<en>(x, l.pressure, l.shear, l.transverse_shear);
    for (int a = 0; a < en; ++a)
      for (int c = 0; c < DofsPerNode; ++c) out(node[a] * DofsPerNode + c) += f(a, c);
  }

  std::unordered_set<std::uint64_t> wanted_;  ///< the ordered pairs indexed (found or not)
  std::unordered_map<std::uint64_t, EdgeRef> edges_;
};

}  // namespace gapfe

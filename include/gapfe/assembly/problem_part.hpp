#pragma once
// One part of a Problem partitioned over several processes (core/subdomain.hpp), made from the whole
// Problem that every process builds (the deck and its mesh are read everywhere): the part's cells and nodes
// (mesh/cell_partition.hpp), the materials, and the loads and conditions that fall on it, renumbered.
//
// Bad input must fail the same way on every process: a part that threw alone would leave the others waiting
// in their next collective call. So the whole problem is checked here before it is cut (the checks a part's
// Assembler repeats then pass), and loads given later, in the whole mesh's numbering (set_part_loads), are
// checked as a whole before each part keeps its own.
//
// What a part keeps: every card at one of its nodes, a ghost's with its prescribed components only (a card
// force is a nodal force, added once, by the node's owner: the parts' sum counts it once); the edge loads on
// its cells' edges (an edge, M -> N with the element on its left, belongs to one cell); the temperatures at
// its nodes; the inertia load and the materials as they are.
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include "gapfe/assembly/cells.hpp"
#include "gapfe/assembly/dof_map.hpp"
#include "gapfe/assembly/edge_index.hpp"
#include "gapfe/assembly/problem_check.hpp"
#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/core/pair_key.hpp"
#include "gapfe/mesh/cell_partition.hpp"
#include "gapfe/problem/problem.hpp"

namespace gapfe {

/// The ends of the gap pairs, which every part keeps (mesh_part's shared nodes): every part evaluates every
/// pair, so contact decisions are the same everywhere.
inline std::vector<int> pair_nodes(const std::vector<GapPair>& pairs) {
  std::vector<int> nodes;
  nodes.reserve(2 * pairs.size());
  for (const GapPair& p : pairs) nodes.push_back(p.node_a), nodes.push_back(p.node_b);
  return nodes;
}

/// Gap pairs of the whole mesh in a part's local numbering (their ends are on every part: pair_nodes).
inline std::vector<GapPair> part_pairs(const PartLayout& layout, std::vector<GapPair> pairs) {
  for (GapPair& p : pairs) {
    p.node_a = layout.local_node[static_cast<std::size_t>(p.node_a)];
    p.node_b = layout.local_node[static_cast<std::size_t>(p.node_b)];
    if (p.node_a < 0 || p.node_b < 0)
      throw InputError("partition: gap element " + std::to_string(p.element + 1) +
                       " has a node the part does not hold (give pair_nodes() to mesh_part)");
  }
  return pairs;
}

/// Nodal conditions and edge loads of the whole problem (whole mesh numbering; `whole_nodes` its nodes)
/// into `part`, a part's Problem: checked as a whole (the errors a whole problem's solve gives), then the
/// part's own are kept, renumbered. Collective over the parts (an edge load no part holds is an error on
/// every part).
template <class M>
void set_part_loads(Problem<M>& part, const std::vector<Vec2>& whole_nodes,
                    const std::vector<NodalCondition>& conditions, const std::vector<EdgeLoad>& edge_loads) {
  constexpr int kNd        = M::kDofsPerNode;
  const Subdomain& domain  = *part.subdomain;
  const PartLayout& layout = domain.layout();
  const int whole          = static_cast<int>(whole_nodes.size());
  const double axis_tol    = 1e-9 * part.mesh.size();  // the whole mesh's size (Mesh::whole_size)
  part.conditions.clear();
  for (const NodalCondition& c : conditions) {
    DofMap<kNd>::check(c, whole,
                       [&](int n) { return whole_nodes[static_cast<std::size_t>(n)](0) <= axis_tol; });
    const int local = layout.local_node[static_cast<std::size_t>(c.node)];
    if (local < 0) continue;
    NodalCondition kept = c;
    kept.node           = local;
    if (!layout.owns(local))
      for (int k = 0; k < 3; ++k)
        if (!c.prescribed(k)) kept.value[static_cast<std::size_t>(k)] = 0.0;
    part.conditions.push_back(kept);
  }

  // Edge loads: those whose edge M -> N is an edge of one of the part's cells. found[2k]: the part holds
  // edge k as given, found[2k + 1]: reversed; summed over the parts, a zero is the whole problem's error.
  const auto local_of = [&](int n) {
    return n >= 0 && n < whole ? layout.local_node[static_cast<std::size_t>(n)] : -1;
  };
  std::unordered_set<int> starts;  // local nodes that begin or end a loaded edge
  for (std::size_t k = 0; k < edge_loads.size(); ++k) {
    check_edge_load<kNd>(edge_loads[k], k);
    const int m = local_of(edge_loads[k].node_m), n = local_of(edge_loads[k].node_n);
    if (m >= 0 && n >= 0) starts.insert(m), starts.insert(n);
  }
  std::unordered_set<std::uint64_t> edges;  // the part's cell edges that start at one of those nodes
  if (!starts.empty())
    for_each_cell<typename M::Element>(
        part.mesh, [&]<class E, std::size_t NPC>(std::type_identity<E>, std::size_t,
                                                 const std::array<int, NPC>& cell, const CellTag&) {
          for (const auto& edge : E::kEdges)
            if (starts.count(cell[edge.front()]))
              edges.insert(pair_key(cell[edge.front()], cell[edge.back()]));
        });
  std::vector<double> found(2 * edge_loads.size(), 0.0);
  for (std::size_t k = 0; k < edge_loads.size(); ++k) {
    const int m = local_of(edge_loads[k].node_m), n = local_of(edge_loads[k].node_n);
    if (m < 0 || n < 0) continue;
    found[2 * k]     = edges.count(pair_key(m, n)) ? 1.0 : 0.0;
    found[2 * k + 1] = edges.count(pair_key(n, m)) ? 1.0 : 0.0;
  }
  std::vector<double> total = found;
  if (!total.empty()) domain.sum(total.data(), static_cast<int>(total.size()));
  part.edge_loads.clear();
  for (std::size_t k = 0; k < edge_loads.size(); ++k) {
    if (total[2 * k] == 0) throw edge_load_error(k, edge_loads[k], total[2 * k + 1] > 0);
    if (found[2 * k] == 0) continue;
    EdgeLoad kept = edge_loads[k];
    kept.node_m = local_of(kept.node_m), kept.node_n = local_of(kept.node_n);
    part.edge_loads.push_back(kept);
  }
}

/// The part of `whole` that `subdomain` describes, its cells and nodes `piece` (mesh_part, whose layout the
/// subdomain was made from); `links`: node pairs that may carry node links, whole numbering (checked here).
/// Collective over the parts.
template <class M>
Problem<M> problem_part(const Problem<M>& whole, Mesh<M::Element::kNodes> piece,
                        std::shared_ptr<const Subdomain> subdomain, const Connectivity<2>& links = {}) {
  // The checks of a whole run, and the bodies nothing holds: every part sees the whole model and would
  // refuse it alike; agreed all the same, so that the parts throw together (core/subdomain.hpp).
  on_every_part(subdomain.get(), [&] {
    check_model(whole, links);
    check_loads(whole);
    check_held<M::kDofsPerNode, typename M::Element>(
        whole.mesh, DofMap<M::kDofsPerNode>::build(whole.mesh, whole.conditions).equation, links);
  });
  const PartLayout& layout = subdomain->layout();
  if (static_cast<int>(piece.nodes.size()) != layout.local_nodes() ||
      static_cast<int>(layout.local_node.size()) != whole.mesh.node_count())
    throw InputError("partition: the part's mesh and its subdomain's layout do not match the whole mesh");
  Problem<M> p;
  p.mesh                  = std::move(piece);
  p.materials             = whole.materials;
  p.inertia               = whole.inertia;
  p.reference_temperature = whole.reference_temperature;
  p.thermal_fraction      = whole.thermal_fraction;
  if (whole.temperature.size() > 0) {
    p.temperature.resize(layout.local_nodes());
    for (int n = 0; n < layout.local_nodes(); ++n)
      p.temperature(n) = whole.temperature(layout.global_node[static_cast<std::size_t>(n)]);
  }
  p.subdomain = std::move(subdomain);
  set_part_loads(p, whole.mesh.nodes, whole.conditions, whole.edge_loads);
  return p;
}

}  // namespace gapfe

#pragma once
// Partitioning a mesh over several processes (core/subdomain.hpp): which part each cell goes to, and one
// part as a mesh of its own with the layout that maps it back. Pure functions of the whole mesh: every
// process computes the same partition from the same mesh, with no communication.
//
// Cells are split by recursive coordinate bisection of their centroids: the cells are cut in two across
// the longer extent of their centroids, in the ratio of the parts on either side, and each half is cut
// again until every part has its cells. Why this, not the I-J grid's index ranges or a graph partitioner:
//   * gapfe's sections are long and thin (tubes, sleeves, barrels) or compact (projectiles, rings); a cut
//     across the longer extent of an I-J tube meets one grid line, the same interface as an index range
//     (the least a grid allows), and it works unchanged on Gmsh meshes and on I-J blocks of any shape;
//   * it needs no adjacency graph and no library (ParMETIS is not in Debian main, and PT-Scotch through
//     PETSc's MatPartitioning would need the graph assembled first), and it is deterministic, so every
//     rank agrees on it without exchanging a byte;
//   * equal cell counts balance the work: assembly, return maps and recovery cost the same per cell, and
//     the direct solver balances its own factorization.
// A graph partitioner would cut fewer edges only on meshes whose parts are far from convex, which the
// structures here are not.
//
// Nodes: a node belongs to the lowest-numbered part among the cells that use it (a node no cell uses, to
// part 0). A part's mesh holds the nodes of its cells and the `shared_nodes` every part must see (the ends
// of gap pairs: every part evaluates every pair, core/subdomain.hpp), owned ones first, each group in the
// whole mesh's order.
#include <algorithm>
#include <climits>
#include <numeric>
#include <string>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/subdomain.hpp"
#include "gapfe/mesh/mesh.hpp"

namespace gapfe {

/// The part (0 .. parts - 1) of every cell of `mesh`: its cells first, then its triangles. Part k gets
/// floor or ceil of cells / parts cells.
template <int N>
std::vector<int> partition_cells(const Mesh<N>& mesh, int parts) {
  const std::size_t cells = mesh.cells.size(), total = cells + mesh.triangles.size();
  if (parts < 1) throw InputError("partition: the number of parts must be at least 1");
  if (static_cast<std::size_t>(parts) > total)
    throw InputError("partition: " + std::to_string(parts) + " parts for a mesh of " + std::to_string(total) +
                     " cells; use at most one process per cell");
  std::vector<Vec2> centre(total);
  for (std::size_t e = 0; e < cells; ++e) {
    Vec2 c = Vec2::Zero();
    for (const int n : mesh.cells[e]) c += mesh.nodes[n];
    centre[e] = c / N;
  }
  for (std::size_t e = 0; e < mesh.triangles.size(); ++e) {
    Vec2 c = Vec2::Zero();
    for (const int n : mesh.triangles[e]) c += mesh.nodes[n];
    centre[cells + e] = c / 3;
  }
  std::vector<int> order(total), part(total, 0);
  std::iota(order.begin(), order.end(), 0);
  // Cut order[first, last) into `count` parts numbered from `first_part` (iteratively, a stack of ranges).
  struct Range {
    std::size_t first, last;
    int first_part, count;
  };
  std::vector<Range> todo{{0, total, 0, parts}};
  while (!todo.empty()) {
    const Range r = todo.back();
    todo.pop_back();
    if (r.count == 1) {
      for (std::size_t k = r.first; k < r.last; ++k) part[static_cast<std::size_t>(order[k])] = r.first_part;
      continue;
    }
    Vec2 lo = centre[static_cast<std::size_t>(order[r.first])], hi = lo;
    for (std::size_t k = r.first; k < r.last; ++k)
      lo = lo.cwiseMin(centre[static_cast<std::size_t>(order[k])]),
      hi = hi.cwiseMax(centre[static_cast<std::size_t>(order[k])]);
    const int axis          = (hi - lo)(1) > (hi - lo)(0) ? 1 : 0;
    const int left_parts    = r.count / 2;
    const std::size_t split = r.first + (r.last - r.first) * static_cast<std::size_t>(left_parts) /
                                            static_cast<std::size_t>(r.count);
    // Ties in the coordinate are broken by the cell's number, so the cut is the same on every process.
    std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(r.first),
                     order.begin() + static_cast<std::ptrdiff_t>(split),
                     order.begin() + static_cast<std::ptrdiff_t>(r.last), [&](int a, int b) {
                       const double ca = centre[static_cast<std::size_t>(a)](axis),
                                    cb = centre[static_cast<std::size_t>(b)](axis);
                       return ca < cb || (ca == cb && a < b);
                     });
    todo.push_back({r.first, split, r.first_part, left_parts});
    todo.push_back({split, r.last, r.first_part + left_parts, r.count - left_parts});
  }
  return part;
}

/// One part of a partitioned mesh: its cells and nodes as a mesh of their own, and where they came from.
template <int N>
struct MeshPart {
  Mesh<N> mesh;       ///< local numbering (PartLayout); mesh.whole_size = the whole mesh's size()
  PartLayout layout;  ///< local <-> whole, owned nodes, ghosts' owners
};

/// Part `part` of `whole` under `cell_part` (partition_cells: cells, then triangles): its cells, the nodes
/// they use and `shared_nodes` (nodes of the whole mesh every part keeps, such as the ends of gap pairs).
template <int N>
MeshPart<N> mesh_part(const Mesh<N>& whole, const std::vector<int>& cell_part, int parts, int part,
                      const std::vector<int>& shared_nodes = {}) {
  const std::size_t cells = whole.cells.size(), total = cells + whole.triangles.size();
  const int nodes = whole.node_count();
  if (cell_part.size() != total)
    throw InputError("partition: one part per cell expected, got " + std::to_string(cell_part.size()) +
                     " for " + std::to_string(total) + " cells");
  if (part < 0 || part >= parts)
    throw InputError("partition: part " + std::to_string(part) + " out of range");
  // Owner: the lowest part among a node's cells; a node that no cell uses goes to part 0.
  std::vector<int> owner(static_cast<std::size_t>(nodes), INT_MAX);
  std::vector<char> here(static_cast<std::size_t>(nodes), 0);
  const auto visit = [&](const auto& cell, int p) {
    if (p < 0 || p >= parts) throw InputError("partition: a cell's part is out of range");
    for (const int n : cell) {
      owner[static_cast<std::size_t>(n)] = std::min(owner[static_cast<std::size_t>(n)], p);
      if (p == part) here[static_cast<std::size_t>(n)] = 1;
    }
  };
  for (std::size_t e = 0; e < cells; ++e) visit(whole.cells[e], cell_part[e]);
  for (std::size_t e = 0; e < whole.triangles.size(); ++e) visit(whole.triangles[e], cell_part[cells + e]);
  for (int& o : owner)
    if (o == INT_MAX) o = 0;
  for (const int n : shared_nodes) {
    if (n < 0 || n >= nodes)
      throw InputError("partition: shared node " + std::to_string(n + 1) + " out of range");
    here[static_cast<std::size_t>(n)] = 1;
  }
  // Each node's index among its owner's owned nodes (the owner's local number for it).
  std::vector<int> index(static_cast<std::size_t>(nodes)), owned_count(static_cast<std::size_t>(parts), 0);
  for (int n = 0; n < nodes; ++n) {
    const auto o                       = static_cast<std::size_t>(owner[static_cast<std::size_t>(n)]);
    index[static_cast<std::size_t>(n)] = owned_count[o]++;
    if (static_cast<int>(o) == part) here[static_cast<std::size_t>(n)] = 1;
  }

  MeshPart<N> out;
  PartLayout& l = out.layout;
  l.part = part, l.parts = parts;
  l.whole_cells     = static_cast<int>(cells);
  l.whole_triangles = static_cast<int>(whole.triangles.size());
  l.local_node.assign(static_cast<std::size_t>(nodes), -1);
  for (int pass = 0; pass < 2; ++pass)  // owned nodes, then ghosts
    for (int n = 0; n < nodes; ++n) {
      if (!here[static_cast<std::size_t>(n)] || (owner[static_cast<std::size_t>(n)] == part) != (pass == 0))
        continue;
      l.local_node[static_cast<std::size_t>(n)] = static_cast<int>(l.global_node.size());
      l.global_node.push_back(n);
      if (pass == 1)
        l.ghost_part.push_back(owner[static_cast<std::size_t>(n)]),
            l.ghost_index.push_back(index[static_cast<std::size_t>(n)]);
    }
  l.owned_nodes = owned_count[static_cast<std::size_t>(part)];

  Mesh<N>& m = out.mesh;
  m.nodes.reserve(l.global_node.size());
  for (const int n : l.global_node) m.nodes.push_back(whole.nodes[static_cast<std::size_t>(n)]);
  const auto local = [&](auto cell) {
    for (int& n : cell) n = l.local_node[static_cast<std::size_t>(n)];
    return cell;
  };
  for (std::size_t e = 0; e < cells; ++e)
    if (cell_part[e] == part) {
      l.global_cell.push_back(static_cast<int>(e));
      m.cells.push_back(local(whole.cells[e]));
      if (!whole.cell_tags.empty()) m.cell_tags.push_back(whole.cell_tags[e]);
    }
  for (std::size_t e = 0; e < whole.triangles.size(); ++e)
    if (cell_part[cells + e] == part) {
      l.global_triangle.push_back(static_cast<int>(e));
      m.triangles.push_back(local(whole.triangles[e]));
      if (!whole.triangle_tags.empty()) m.triangle_tags.push_back(whole.triangle_tags[e]);
    }
  m.whole_size = whole.size();
  return out;
}

}  // namespace gapfe

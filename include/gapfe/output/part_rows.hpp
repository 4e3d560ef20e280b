#pragma once
// A partitioned run's share of the result files (docs/cluster.md "Output"): each process writes the rows of
// the whole mesh that it holds, numbered as the whole mesh's, so that no process gathers every result.
//  * its VTU piece holds every node and cell of its part (ghost nodes too, with their owners' values: a
//    cell's piece must hold its nodes); the pieces' cells partition the deck's elements;
//  * its tables hold the nodes it owns and its cells: every node and element is in exactly one table.
#include <cstddef>
#include <vector>

#include "gapfe/core/error.hpp"
#include "gapfe/core/subdomain.hpp"
#include "gapfe/input/scene.hpp"

namespace gapfe {

struct PartRows {
  int part = 0, parts = 1;             ///< this process's part (an MPI rank) and how many there are
  const PartLayout* layout = nullptr;  ///< the part's place in the whole mesh (core/subdomain.hpp)
  /// Per local cell, in the order of the part's centroid values (its cells, then its triangles): the deck
  /// element (grid cell) it is.
  std::vector<int> element;

  int owned_nodes() const { return layout->owned_nodes; }
  /// The whole mesh's node of local node n (owned nodes first).
  int node(int n) const { return layout->global_node[static_cast<std::size_t>(n)]; }
  int local_nodes() const { return layout->local_nodes(); }
  /// The local node of whole node n, -1 where the part holds none.
  int local(int n) const { return layout->local_node[static_cast<std::size_t>(n)]; }
};

/// The rows `layout`'s part writes of `scene`'s results. Every deck element is a cell of the mesh the run
/// partitions (a quadrilateral or a triangle: GridCell::group_index), so each is in exactly one part.
inline PartRows part_rows(const Scene& scene, const PartLayout& layout) {
  const IJGrid& g = scene.grid;
  std::vector<int> of_cell(static_cast<std::size_t>(layout.whole_cells + layout.whole_triangles), -1);
  for (std::size_t e = 0; e < g.cells.size(); ++e) {
    const GridCell& c = g.cells[e];
    of_cell[static_cast<std::size_t>((c.corners == 4 ? 0 : layout.whole_cells) + c.group_index)] =
        static_cast<int>(e);
  }
  PartRows rows{layout.part, layout.parts, &layout, {}};
  const auto add = [&](int whole) {
    const int e = of_cell[static_cast<std::size_t>(whole)];
    if (e < 0) throw SolveError("partition: a cell of the part is no deck element");  // a broken layout
    rows.element.push_back(e);
  };
  for (const int c : layout.global_cell) add(c);
  for (const int t : layout.global_triangle) add(layout.whole_cells + t);
  return rows;
}

}  // namespace gapfe

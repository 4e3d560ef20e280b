#pragma once
// Mesh: nodal (r, z) and cells. A structured I-J grid gives quadrilaterals plus, along boundary
// diagonals, 3-corner cells; so a mesh holds cells of the model's element (NodesPerCell nodes) and
// triangles (3 nodes, or 6 beside quadratic cells), each with a material index and a material frame.
// Connectivity is 0-based, counterclockwise in the (r, z) plane (element to the left of each edge).
#include <array>
#include <vector>

#include "gapfe/core/material_frame.hpp"
#include "gapfe/core/types.hpp"

namespace gapfe {

/// An element group: `count` cells of `NodesPerCell` nodes, node (e, a) = nodes[e][a].
template <std::size_t NodesPerCell>
using Connectivity = std::vector<std::array<int, NodesPerCell>>;

/// Per-cell attributes: which material (index into the model's material list) and its axes.
struct CellTag {
  int material = 0;
  MaterialFrame frame{};
};

template <int NodesPerCell>
struct Mesh {
  static constexpr int kNodesPerCell = NodesPerCell;
  /// Nodes of a 3-corner cell: 6 (Tri6: corners, then the mid-sides 0-1, 1-2, 2-0) beside quadratic cells
  /// (8-node quadrilaterals, 6-node triangles), else 3 (the constant-strain Tri3).
  static constexpr int kTriangleNodes = NodesPerCell == 8 || NodesPerCell == 6 ? 6 : 3;
  std::vector<Vec2> nodes;                                 ///< (r, z) [length]
  std::vector<std::array<int, NodesPerCell>> cells;        ///< the model's element
  std::vector<CellTag> cell_tags;                          ///< parallel to cells (empty: all default)
  std::vector<std::array<int, kTriangleNodes>> triangles;  ///< 3-corner cells
  std::vector<CellTag> triangle_tags;                      ///< parallel to triangles (empty: all default)
  /// A part of a partitioned mesh (mesh/cell_partition.hpp) keeps the whole mesh's size() here, so that the
  /// tolerances relative to it (nodes on the axis, gap overlaps) are the same on every part; 0: whole.
  double whole_size = 0;

  int node_count() const { return static_cast<int>(nodes.size()); }
  CellTag cell_tag(std::size_t e) const { return cell_tags.empty() ? CellTag{} : cell_tags[e]; }
  CellTag triangle_tag(std::size_t e) const { return triangle_tags.empty() ? CellTag{} : triangle_tags[e]; }

  /// Largest extent of the mesh in r or z, for relative tolerances [length].
  double size() const {
    if (whole_size > 0) return whole_size;
    Vec2 lo = nodes.front(), hi = nodes.front();
    for (const auto& x : nodes) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    return (hi - lo).maxCoeff();
  }
};

}  // namespace gapfe

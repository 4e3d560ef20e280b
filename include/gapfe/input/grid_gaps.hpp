#pragma once
// The gap elements of a deck's I-J grid (material 2 blocks) and their node pairs: which corners face each
// other across each gap element (contact/gap_pairs.hpp, gap_element_pairs), by SAAC's one LGAP or SAAC2's
// IJDIR per block, and which gap elements stay soft (corners, seed Figure 10).
#include <string>
#include <vector>

#include "gapfe/contact/gap_pairs.hpp"
#include "gapfe/core/error.hpp"
#include "gapfe/mesh/ij_grid.hpp"

namespace gapfe {

/// The gap elements of an I-J grid and their pairs.
struct GapLayout {
  std::vector<GapPair> pairs;
  std::vector<int> soft;       ///< gap elements without pairs (corners, IJDIR 0, triangles), 0-based
  std::vector<int> direction;  ///< per grid cell: the direction used (0 for soft and structural cells)
};

/// Pairs of the grid cells with `is_gap`, each closing along `direction[cell]` (SAAC2's IJDIR), or along
/// `global_direction` for all when it is 1 or 2 (SAAC's single LGAP). A gap cell with gap neighbours
/// across both an I face and a J face is a corner (seed Figure 10) and stays soft, as do IJDIR = 0 and
/// 3-corner cells.
inline GapLayout grid_gap_pairs(const IJGrid& grid, const std::vector<char>& is_gap,
                                const std::vector<int>& direction, int global_direction = 0) {
  GapLayout out;
  out.direction.assign(grid.cells.size(), 0);
  std::vector<int> cell_at(grid.box_points(), -1);  // a cell's lower-left corner lies in the box
  const auto at = [&](int i, int j) -> int { return grid.in_box(i, j) ? cell_at[grid.box_index(i, j)] : -1; };
  for (std::size_t e = 0; e < grid.cells.size(); ++e)
    if (is_gap[e]) cell_at[grid.box_index(grid.cells[e].i, grid.cells[e].j)] = static_cast<int>(e);
  for (std::size_t e = 0; e < grid.cells.size(); ++e) {
    if (!is_gap[e]) continue;
    const GridCell& c = grid.cells[e];
    const int dir     = global_direction != 0 ? global_direction : direction[e];
    const bool corner = global_direction == 0 && (at(c.i - 1, c.j) >= 0 || at(c.i + 1, c.j) >= 0) &&
                        (at(c.i, c.j - 1) >= 0 || at(c.i, c.j + 1) >= 0);
    if (dir == 0 || corner || c.corners != 4) {
      out.soft.push_back(static_cast<int>(e));
      continue;
    }
    // The seed's IX order by grid position, whatever the orientation of the mesh cell.
    const std::array<int, 4> ix{grid.node(c.i, c.j), grid.node(c.i + 1, c.j), grid.node(c.i + 1, c.j + 1),
                                grid.node(c.i, c.j + 1)};
    for (const GapPair& p : gap_element_pairs(static_cast<int>(e), ix, dir, grid.nodes))
      out.pairs.push_back(p);
    out.direction[e] = dir;
  }
  return out;
}

}  // namespace gapfe

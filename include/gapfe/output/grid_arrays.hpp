#pragma once
// What every file of a run draws from the deck's grid: its cells as VTU cells, the cell arrays of the deck's
// material and element numbers, the outline of its cells, and the fill of each material in the pictures.
#include <array>
#include <vector>

#include "gapfe/input/scene.hpp"
#include "gapfe/output/svg_canvas.hpp"
#include "gapfe/output/vtu_writer.hpp"

namespace gapfe::detail {

/// The grid's cells as VTU cells: corners, then the middle nodes of quadratic cells (VTK's quadratic
/// triangle and quadrilateral take them in GridCell::mid's order).
inline VtuCells grid_cells(const IJGrid& g) {
  VtuCells cells;
  for (const auto& c : g.cells) {
    if (c.mid[0] < 0) {
      cells.add(c.node.data(), c.corners);
      continue;
    }
    std::array<int, 8> nodes{};
    for (int k = 0; k < c.corners; ++k) nodes[k] = c.node[k], nodes[c.corners + k] = c.mid[k];
    cells.add(nodes.data(), 2 * c.corners);
  }
  return cells;
}

/// Cell arrays every VTU of a deck carries: the deck's material number and the element number.
inline std::vector<VtuField> element_ids(const Scene& s) {
  std::vector<VtuField> f{{"material", 1, {}, true}, {"element", 1, {}, true}};
  for (std::size_t e = 0; e < s.grid.cells.size(); ++e)
    f[0].values.push_back(s.material_id[e]), f[1].values.push_back(static_cast<double>(e + 1));
  return f;
}

/// The outline (output/svg_canvas.hpp, outline_sides) of an I-J grid's cells.
inline std::vector<std::array<int, 2>> outline_edges(const IJGrid& g, const std::vector<int>& material) {
  return outline_sides(
      g.cells.size(),
      [&](std::size_t e, auto&& side) {
        const GridCell& c = g.cells[e];
        for (int k = 0; k < c.corners; ++k) side(c.node[k], c.node[(k + 1) % c.corners]);
      },
      material);
}

inline constexpr const char* kMaterialFill[] = {"#dbe8f6", "#f6e3c9", "#d8f0d2",
                                                "#eed8f0", "#f3f0c8", "#d5eeee"};

}  // namespace gapfe::detail

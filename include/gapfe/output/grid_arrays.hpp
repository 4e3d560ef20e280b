#pragma once
// What every file of a run draws from the deck's grid: its cells as VTU cells, the cell arrays of the deck's
// material and element numbers, the outline of its cells, and the fill of each material in the pictures.
#include <array>
#include <vector>

#include "gapfe/input/scene.hpp"
#include "gapfe/output/part_rows.hpp"
#include "gapfe/output/svg_canvas.hpp"
#include "gapfe/output/vtu_writer.hpp"

namespace gapfe::detail {

/// The grid's cells as VTU cells: corners, then the middle nodes of quadratic cells (VTK's quadratic
/// triangle and quadrilateral take them in GridCell::mid's order). A part's (`rows`): its cells, in its
/// order, on its local nodes.
inline VtuCells grid_cells(const IJGrid& g, const PartRows* rows = nullptr) {
  VtuCells cells;
  const std::size_t count = rows ? rows->element.size() : g.cells.size();
  for (std::size_t k = 0; k < count; ++k) {
    const GridCell& c = g.cells[rows ? static_cast<std::size_t>(rows->element[k]) : k];
    std::array<int, 8> nodes{};
    const int size = c.mid[0] < 0 ? c.corners : 2 * c.corners;
    for (int m = 0; m < c.corners; ++m) {
      nodes[m] = c.node[m];
      if (size > c.corners) nodes[c.corners + m] = c.mid[m];
    }
    if (rows)
      for (int m = 0; m < size; ++m) nodes[m] = rows->local(nodes[m]);
    cells.add(nodes.data(), size);
  }
  return cells;
}

/// The points of the grid (r, z), or of a part's local nodes.
inline std::vector<Vec2> grid_points(const IJGrid& g, const PartRows* rows = nullptr) {
  if (!rows) return g.nodes;
  std::vector<Vec2> points(static_cast<std::size_t>(rows->local_nodes()));
  for (int n = 0; n < rows->local_nodes(); ++n) points[static_cast<std::size_t>(n)] = g.nodes[rows->node(n)];
  return points;
}

/// Cell arrays every VTU of a deck carries: the deck's material number and the element number (of a part's
/// cells, in its order, with `rows`).
inline std::vector<VtuField> element_ids(const Scene& s, const PartRows* rows = nullptr,
                                         bool declared_only = false) {
  std::vector<VtuField> f{{"material", 1, {}, true}, {"element", 1, {}, true}};
  if (declared_only) return f;  // their names and types (a .pvtu's declarations)
  const std::size_t count = rows ? rows->element.size() : s.grid.cells.size();
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t e = rows ? static_cast<std::size_t>(rows->element[k]) : k;
    f[0].values.push_back(s.material_id[e]), f[1].values.push_back(static_cast<double>(e + 1));
  }
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

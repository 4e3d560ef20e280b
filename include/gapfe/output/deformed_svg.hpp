#pragma once
// deformed.svg: a run's last increment drawn on its deformed mesh.
#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "gapfe/input/scene.hpp"
#include "gapfe/output/field_plot.hpp"
#include "gapfe/output/grid_arrays.hpp"
#include "gapfe/output/svg_canvas.hpp"

namespace gapfe {

/// Above this many cells deformed.svg draws the outline (boundary and material interfaces) instead
/// of every cell: a picture of 1e5 cells shows no cell, and writing it cost 10% of a 1e5-equation run.
inline constexpr std::size_t kSvgCellLimit = 20000;

/// deformed.svg: the last increment's deformed mesh over the undeformed outline, displacements
/// magnified to 5% of the section (a 1-2-5 factor, printed); gap elements coloured by their state.
/// Meshes of more than kSvgCellLimit cells: the deformed outline over the undeformed one. `gap_state`: the
/// gap_fields cell array of the increment (empty without gaps).
inline void write_deformed_svg(const std::string& dir, const Scene& scene,
                               const Eigen::Matrix<double, Eigen::Dynamic, 3>& displacement,
                               const std::vector<double>& gap_state, const std::string& title) {
  const IJGrid& g = scene.grid;
  if (displacement.rows() != g.node_count()) return;  // no increment written
  const double factor =
      picture_magnification(g.nodes, displacement.leftCols<2>().rowwise().norm().maxCoeff());
  std::vector<Vec2> deformed(g.nodes), both(g.nodes);
  for (int n = 0; n < g.node_count(); ++n) {
    deformed[n] = g.nodes[n] + factor * displacement.row(n).head<2>().transpose();
    both.push_back(deformed[n]);
  }
  std::string factor_text;
  detail::append_number(factor_text, factor);
  detail::SvgCanvas svg(both, title + ": deformed x " + factor_text + " over the undeformed outline (grey)",
                        50);
  const bool gaps = !gap_state.empty();
  if (g.cells.size() > kSvgCellLimit) {
    const auto edges = detail::outline_edges(g, scene.material_id);
    for (const std::vector<Vec2>* x : {&g.nodes, static_cast<const std::vector<Vec2>*>(&deformed)})
      for (const auto& [a, b] : edges)
        svg.polygon(std::array<Vec2, 2>{(*x)[a], (*x)[b]}, 2, "none", x == &g.nodes ? "#b0b0b0" : "#333",
                    x == &g.nodes ? 0.5 : 0.8);
  }
  for (const auto& c : g.cells) {
    if (g.cells.size() > kSvgCellLimit) break;
    std::array<Vec2, 4> x;
    for (int k = 0; k < c.corners; ++k) x[k] = g.nodes[c.node[k]];
    svg.polygon(x, c.corners, "none", "#b0b0b0", 0.5);
  }
  // Structural cells first, then the gap elements on top with a heavy outline in their state's colour:
  // gap elements are usually slivers, and a sliver's outline is what stays visible.
  for (const bool gap_pass : {false, true})
    for (std::size_t e = 0; e < g.cells.size(); ++e) {
      const double state = gaps ? gap_state[e] : 0;
      if ((state != 0) != gap_pass || (!gap_pass && g.cells.size() > kSvgCellLimit)) continue;
      const GridCell& c = g.cells[e];
      std::array<Vec2, 4> x;
      for (int k = 0; k < c.corners; ++k) x[k] = deformed[c.node[k]];
      if (!gap_pass) {
        svg.polygon(x, c.corners, detail::kMaterialFill[(std::max(scene.material_id[e], 1) - 1) % 6], "#333",
                    0.6);
        continue;
      }
      const char* colour = state < 0 ? "#8c8c8c" : state == 1 ? "#1f77b4" : "#d62728";
      svg.polygon(x, c.corners, colour, colour, 3.0);
    }
  if (gaps)
    svg.text(10, svg.height - 12, 13,
             "gap elements: red = closed (a node pair in contact), blue = open, grey = soft throughout "
             "(corners, IJDIR 0)");
  svg.save(dir + "/deformed.svg");
}

}  // namespace gapfe
